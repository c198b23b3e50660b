// lieservo/sampling.hpp — umbrella header for seeded random draws and training-data sampling
// (paper Section 3.1.1 (sec:surface_contact_poses), Section 3.1.2 (sec:data_collection)).
#pragma once

#include <lieservo/sampling/contact_sampling.hpp>
#include <lieservo/sampling/random.hpp>

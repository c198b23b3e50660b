// lieservo/sampling.hpp — umbrella header for training-data sampling
// (paper sec:surface_contact_poses, sec:data_collection).
#pragma once

#include <lieservo/sampling/contact_sampling.hpp>

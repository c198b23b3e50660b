// lieservo/lieservo.hpp — umbrella header of the whole library (Eigen only):
// status codes, units, Lie groups, estimation, control, real-time utilities, sampling.
// Include the area headers (e.g. <lieservo/groups.hpp>) instead to compile less.
#pragma once

#include "control.hpp"
#include "estimation.hpp"
#include "groups.hpp"
#include "realtime.hpp"
#include "sampling.hpp"
#include "status.hpp"
#include "units.hpp"

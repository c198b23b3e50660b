// lieservo/lieservo.hpp — umbrella header of the core: status codes, units, Lie groups.
#pragma once

#include "groups.hpp"
#include "status.hpp"
#include "units.hpp"

// lieservo/groups.hpp — all Lie groups of the core: SO(2), SE(2), SO(3), SE(3), and the
// left-perturbation operators ⊕/⊖ (lplus, lminus) shared by all of them.
#pragma once
#include <lieservo/detail/options_push.hpp>

#include <lieservo/groups/perturbation.hpp>
#include <lieservo/groups/se2.hpp>
#include <lieservo/groups/se3.hpp>
#include <lieservo/groups/so2.hpp>
#include <lieservo/groups/so3.hpp>

#include <lieservo/detail/options_pop.hpp>

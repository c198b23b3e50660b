// lieservo/estimation.hpp — estimation on Lie groups: concentrated Gaussians, data fusion
// (Algorithm 3, alg:se3_data_fusion) and the discriminative Bayesian filter (Algorithm 2, alg:se3_bayes_filter).
// See docs/estimation.md.
#pragma once

#include "estimation/bayes_filter.hpp"
#include "estimation/chi_square.hpp"
#include "estimation/concentrated_gaussian.hpp"
#include "estimation/fusion.hpp"
#include "estimation/jacobian_policy.hpp"

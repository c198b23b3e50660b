// lieservo/estimation.hpp — estimation on Lie groups: concentrated Gaussians, data fusion
// (Algorithm 3, alg:se3_data_fusion) and the discriminative Bayesian filter (Algorithm 2, alg:se3_bayes_filter).
// See docs/estimation.md.
#pragma once
#include <lieservo/detail/options_push.hpp>

#include <lieservo/estimation/bayes_filter.hpp>
#include <lieservo/estimation/chi_square.hpp>
#include <lieservo/estimation/concentrated_gaussian.hpp>
#include <lieservo/estimation/fusion.hpp>
#include <lieservo/estimation/jacobian_policy.hpp>

#include <lieservo/detail/options_pop.hpp>

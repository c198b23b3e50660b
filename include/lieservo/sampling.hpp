// lieservo/sampling.hpp — umbrella header for seeded random draws (the same sequence from a
// seed on every platform). The paper's training-data sampling (Algorithm 1) is an example:
// examples/collection/contact_sampling.hpp.
#pragma once
#include <lieservo/detail/options_push.hpp>

#include <lieservo/sampling/random.hpp>

#include <lieservo/detail/options_pop.hpp>

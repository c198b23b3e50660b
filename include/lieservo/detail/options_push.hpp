// lieservo/detail/options_push.hpp — opens the region of one lieservo header (no include guard: every
// header opens with it and closes with options_pop.hpp, as Eigen's headers do with
// DisableStupidWarnings.h).
//
// LIESERVO_VAR_TRACKING_ASSIGNMENTS (docs/performance_design.md, "Compile time for includers"): 0
// compiles the headers' functions, and Eigen's when it is first included through them, as with
// -fno-var-tracking-assignments; 1 leaves the includer's flags alone. The default is 0 for GCC
// under AddressSanitizer or ThreadSanitizer and 1 elsewhere. There GCC's variable tracking over the
// sanitizers' checks in Eigen's expressions is most of the compile: the README's loop with
// -O1 -g -fsanitize=address,undefined takes 46 s with 0 against 138 s with 1 on the
// 2-core VM (docs/performance.md). Locations of variables in optimised code are coarser in the
// debugger; the checks themselves are unchanged. Define it before the first lieservo include, or
// with -DLIESERVO_VAR_TRACKING_ASSIGNMENTS=0|1.
#include <lieservo/detail/sanitizers.hpp>

#ifndef LIESERVO_VAR_TRACKING_ASSIGNMENTS
#if defined(__GNUC__) && !defined(__clang__) && defined(LIESERVO_DETAIL_SANITIZED)
#define LIESERVO_VAR_TRACKING_ASSIGNMENTS 0
#else
#define LIESERVO_VAR_TRACKING_ASSIGNMENTS 1
#endif
#endif

#if !LIESERVO_VAR_TRACKING_ASSIGNMENTS && defined(__GNUC__) && !defined(__clang__)
#pragma GCC push_options
#pragma GCC optimize("no-var-tracking-assignments")
#endif

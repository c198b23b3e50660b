// lieservo/detail/flatten.hpp — forced inlining on the real-time path, and the switch that turns it off.
//
// LIESERVO_FLATTEN: inline every call made inside one hot function. GCC's inliner decides per
// call site and per translation unit: in a file that instantiates many templates it may leave
// even a 6-element Eigen product as an out-of-line call, three of them in one PID step (≈ 150
// extra instructions, measured with callgrind), and SE(3) exp's own helpers (a third of its
// time). Flattening the real-time entry points and the group's exp and log makes their cost
// independent of the file they are compiled in. Forcing the helpers inline one by one
// (LIESERVO_ALWAYS_INLINE alone) does not: GCC then leaves Eigen's 3×3 kernels out of line instead.
//
// LIESERVO_FORCE_INLINE (docs/performance_design.md, "Compile time for includers"): 1 keeps the attributes, 0 drops
// them (LIESERVO_FLATTEN becomes nothing, LIESERVO_ALWAYS_INLINE plain `inline`). Define it
// before the first lieservo include, or with -DLIESERVO_FORCE_INLINE=0|1. By default it is 1 in
// optimised builds and 0 where forcing buys nothing and costs the includer's compile time:
//   - without optimisation (-O0: no __OPTIMIZE__), a debug build;
//   - under AddressSanitizer or ThreadSanitizer (detail/sanitizers.hpp), where GCC 12 compiled the
//     README's loop with the attributes in 558 s and 5.0 GiB, without them in about 100 s; the
//     rest of that cost is variable tracking, which options_push.hpp's switch takes away.
#pragma once
#include <lieservo/detail/options_push.hpp>

#include <Eigen/Core>

#include <lieservo/detail/sanitizers.hpp>

#ifndef LIESERVO_FORCE_INLINE
#if !defined(__OPTIMIZE__) || defined(LIESERVO_DETAIL_SANITIZED)
#define LIESERVO_FORCE_INLINE 0
#else
#define LIESERVO_FORCE_INLINE 1
#endif
#endif

#if LIESERVO_FORCE_INLINE && (defined(__GNUC__) || defined(__clang__))
#define LIESERVO_FLATTEN __attribute__((flatten))
#else
#define LIESERVO_FLATTEN
#endif

// LIESERVO_FLATTEN_GCC: the same for GCC alone, on functions that clang already compiles well
// and that flattening makes slower there (the fusion's loop: 10 % with clang 14).
#if LIESERVO_FORCE_INLINE && defined(__GNUC__) && !defined(__clang__)
#define LIESERVO_FLATTEN_GCC __attribute__((flatten))
#else
#define LIESERVO_FLATTEN_GCC
#endif

// LIESERVO_ALWAYS_INLINE: Eigen's always-inline on the small group kernels, under the same switch.
#if LIESERVO_FORCE_INLINE
#define LIESERVO_ALWAYS_INLINE EIGEN_ALWAYS_INLINE
#else
#define LIESERVO_ALWAYS_INLINE inline
#endif

#include <lieservo/detail/options_pop.hpp>

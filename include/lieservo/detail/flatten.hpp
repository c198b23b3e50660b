// lieservo/detail/flatten.hpp — LIESERVO_FLATTEN: inline every call made inside one hot function.
//
// GCC's inliner decides per call site and per translation unit: in a file that instantiates many
// templates it may leave even a 6-element Eigen product as an out-of-line call, three of them in
// one PID step (≈ 150 extra instructions, measured with callgrind), and SE(3) exp's own helpers
// (a third of its time). Flattening the real-time entry points and the group's exp and log makes
// their cost independent of the file they are compiled in. Forcing the helpers inline one by one
// (EIGEN_ALWAYS_INLINE) does not: GCC then leaves Eigen's 3×3 kernels out of line instead.
#pragma once

#if defined(__GNUC__) || defined(__clang__)
#define LIESERVO_FLATTEN __attribute__((flatten))
#else
#define LIESERVO_FLATTEN
#endif

// LIESERVO_FLATTEN_GCC: the same for GCC alone, on functions that clang already compiles well
// and that flattening makes slower there (the fusion's loop: 10 % with clang 14).
#if defined(__GNUC__) && !defined(__clang__)
#define LIESERVO_FLATTEN_GCC __attribute__((flatten))
#else
#define LIESERVO_FLATTEN_GCC
#endif

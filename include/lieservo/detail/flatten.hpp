// lieservo/detail/flatten.hpp — LIESERVO_FLATTEN: inline every call made inside one hot function.
//
// GCC's inliner decides per call site and per translation unit: in a file that instantiates many
// templates it may leave even a 6-element Eigen product as an out-of-line call, three of them in
// one PID step (≈ 150 extra instructions, measured with callgrind). Flattening the real-time
// entry points makes their cost independent of the file they are compiled in.
#pragma once

#if defined(__GNUC__) || defined(__clang__)
#define LIESERVO_FLATTEN __attribute__((flatten))
#else
#define LIESERVO_FLATTEN
#endif

// lieservo/detail/sanitizers.hpp — whether this translation unit is built with AddressSanitizer or
// ThreadSanitizer: GCC's __SANITIZE_ADDRESS__ / __SANITIZE_THREAD__, clang's __has_feature. Neither
// compiler says whether UndefinedBehaviorSanitizer is on. No includes: options_push.hpp reads it
// before the first Eigen header.
#pragma once

#if !defined(LIESERVO_DETAIL_SANITIZED)
#if defined(__has_feature)
#if __has_feature(address_sanitizer) || __has_feature(thread_sanitizer) || __has_feature(memory_sanitizer)
#define LIESERVO_DETAIL_SANITIZED 1
#endif
#endif
#if defined(__SANITIZE_ADDRESS__) || defined(__SANITIZE_THREAD__)
#define LIESERVO_DETAIL_SANITIZED 1
#endif
#endif

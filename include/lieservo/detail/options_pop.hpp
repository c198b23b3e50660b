// lieservo/detail/options_pop.hpp — closes the region options_push.hpp opened (no include guard).
#if defined(LIESERVO_VAR_TRACKING_ASSIGNMENTS) && !LIESERVO_VAR_TRACKING_ASSIGNMENTS && defined(__GNUC__) && !defined(__clang__)
#pragma GCC pop_options
#endif

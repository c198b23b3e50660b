// franka/lowpass_filter.h (lieservo's libfranka test double) — libfranka's cut-off constants.
#pragma once

namespace franka {
constexpr double kMaxCutoffFrequency = 1000.0;
constexpr double kDefaultCutoffFrequency = 100.0;
}  // namespace franka

// The MuJoCo scene's physical constants that both the scene's MJCF (scene_mjcf.cpp) and the
// world that steps it (mujoco_world.cpp) use. Internal to lieservo_sim.
#pragma once

namespace lieservo::sim::mujoco::model {

inline constexpr double kMm = 1e-3;  // mm → m
// The body that carries a sensor: heavy, so that a contact force of 3 N changes its velocity by
// 0.25 mm/s within a step before the arm sets it again (World::step). The reset takes that
// change from the tip as well, a creep of the gel against what it holds: lighter arms let a
// stuck gel creep (10 kg: 16 % of a 1 mm/s drag), heavier ones slow the solver's convergence.
inline constexpr double kArmMass = 30;        // kg
inline constexpr double kArmInertia = 0.05;   // kg m²
inline constexpr double kGravity = 9.81;
// The gel: the tip is a light body on three slide joints (the sensor frame's axes), springs
// k_gel along z_s and ρ_t k_gel across, behind the arm's nominal tip (the sensor body). A push
// of F on the tip deflects it by F/k whatever the object's mass or inertia; the tip–object
// contact itself is stiff (penetration ≈ 0.03 mm per N: kContactSolref, kContactSolimp). The
// tip's mass sets the gel's natural frequency sqrt(k/m) (283 rad/s at 0.8 N/mm: ω dt = 0.7 at
// the 2.5 ms step, stable under MuJoCo's semi-implicit Euler); its weight is the arm's.
inline constexpr double kTipMass = 0.01;  // kg

}  // namespace lieservo::sim::mujoco::model

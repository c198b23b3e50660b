// lieservo/control/centralised_dual_arm.hpp — dual-arm pushing with a centralised follower
// (paper: Section 3.3.4 (sec:single_dual_arm_controllers), the "centralised, more coordinated"
// alternative to the decentralised leader–follower of DualArmPushing).
//
// The leader runs the paper's pushing controller and the follower its stabilising servo
// (Table 9), each on its own filter, exactly as in DualArmPushing. What is centralised is the
// follower's feedforward: it is computed from both arms' proprioceptive sensor poses X_wL,
// X_wF and the leader's commanded twist u_L = [v_L; ω_L], so that the follower keeps
// opposition (its sensor axis z_F against the leader's z_L) while the leader steers:
//
//   R_FL = R_wFᵀ R_wL,  a = R_FL e_z       the leader's axis in the follower's frame (a = −e_z
//                                          when the two face each other)
//   v_op = k_op (a_x, a_y, 0)              across the follower's axis, norm clipped at v_op,max
//   v_push = R_FL (0, 0, v_L,z)            the leader's push: the object recedes from the
//                                          follower as fast
//   u_F = u_servo,F + [v_op + v_push; 0]
//
// The follower's servo keeps its axis normal to its face, so on a round object its axis turns
// as it moves round: moving along (a_x, a_y) turns it towards −z_L, after a leader whose
// contact slides round the object. A gel that sticks holds both contacts on their material
// points, and they stay opposed without v_op, which then drags the follower sideways against
// the leader's steering (docs/simulation.md: the opposition angle and the misses at each
// gain); so the presets set k_op = 0, and what is centralised is v_push. On parallel faces
// a = −e_z and v_op = 0 whatever k_op.
//
// Lifecycle as DualArmPushing: Options, validate, configure, step (noexcept, allocation-free;
// on any non-ok Status nothing changes), reset. Translation units are the caller's (the
// presets: mm), angles in radians.
#pragma once
#include <lieservo/detail/options_push.hpp>

#include <cmath>

#include <Eigen/Core>

#include <lieservo/control/dual_arm.hpp>
#include <lieservo/groups/perturbation.hpp>
#include <lieservo/groups/se3.hpp>
#include <lieservo/status.hpp>

namespace lieservo {

/// Dual-arm pushing with a centralised follower feedforward (Section 3.3.4,
/// sec:single_dual_arm_controllers): DualArmPushing plus the follower's v_push (and v_op) from
/// both arms' poses and the leader's command (the header comment gives the law). `G`: the pose
/// group, as every controller's (SE3<Scalar>).
template <class G, class Filter = DiscriminativeBayesFilter<G>>
class CentralisedDualArmPushing : public Configurable<CentralisedDualArmPushing<G, Filter>> {
 public:
  using Arms = DualArmPushing<G, Filter>;  ///< the two controllers and filters it drives
  using Scalar = typename G::Scalar;  ///< float or double
  using Group = typename Arms::Group;  ///< SE(3)
  using Tangent = typename Arms::Tangent;  ///< a twist [v; ω]
  using ArmInput = typename Arms::ArmInput;  ///< one arm's measurements for a cycle
  using ArmOutput = typename Arms::ArmOutput;  ///< one arm's result for a cycle
  using Vec3 = Eigen::Matrix<Scalar, 3, 1>;  ///< 3-vector

  /// The arms' options and the opposition term's gain and clip.
  struct Options {
    typename Arms::Options arms{};              ///< the leader's and the follower's controllers
    /// k_op (units/s per unit misalignment ≈ per rad). 0 by default: a gel that sticks holds the
    /// two contacts on their material points, so they stay opposed on their own, and a gain
    /// drags the follower sideways against the leader's steering (docs/control.md).
    Scalar opposition_gain = Scalar(0);
    Scalar max_opposition_speed = Scalar(20);   ///< v_op,max: norm clip of the opposition velocity (units/s)
  };

  CentralisedDualArmPushing() = default;
  /// Configures with `options` (configurationStatus() keeps the result), with the arms' filters.
  CentralisedDualArmPushing(const Options& options, const Filter& leader_filter, const Filter& follower_filter)
      : arms_(options.arms, leader_filter, follower_filter) {
    this->configureOnConstruction(options);
  }

  /// ok, or the first reason: the two arms' options (DualArmPushing::validate),
  /// non_finite_input (a NaN or infinite gain or speed limit), invalid_argument (a negative one).
  static Status validate(const Options& o) noexcept {
    if (const Status s = Arms::validate(o.arms); s != Status::ok) return s;
    if (!std::isfinite(o.opposition_gain) || !std::isfinite(o.max_opposition_speed)) return Status::non_finite_input;
    if (o.opposition_gain < Scalar(0) || o.max_opposition_speed < Scalar(0)) return Status::invalid_argument;
    return Status::ok;
  }

  /// Replaces the options (controller and filter states kept); invalid options change nothing.
  Status configure(const Options& options) noexcept { return this->configureChecked(options); }

  /// Steps both filters and controllers (as DualArmPushing::step), then adds the centralised
  /// feedforward to the follower's twist. Non-finite or non-orthonormal poses and bad
  /// observations: the filters' statuses, nothing changes; a non-finite result:
  /// numerical_failure, nothing changes.
  Status step(const ArmInput& leader_in, const ArmInput& follower_in, Scalar dt, ArmOutput& leader_out,
              ArmOutput& follower_out) noexcept {
    if (const Status c = this->configurationStatus(); c != Status::ok) return c;
    const Arms backup = arms_;
    ArmOutput lo, fo;
    const Status s = arms_.step(leader_in, follower_in, dt, lo, fo);  // its filters check both poses
    if (s != Status::ok) return s;
    Tangent ff = Tangent::Zero();
    if (!arms_.terminated()) {
      const auto R_FL = (follower_in.sensor_pose.rotationMatrix().transpose() * leader_in.sensor_pose.rotationMatrix()).eval();
      // v_op = k_op (a_x, a_y, 0), its norm clipped at v_op,max. The clip is decided on
      // k_op·|a|, which a large gain overflows to +inf and then clips, instead of scaling an
      // overflowed vector to 0.
      const Vec3 a_xy(R_FL(0, 2), R_FL(1, 2), Scalar(0));
      const Scalar a_n = a_xy.norm();
      Vec3 v_op = options_.opposition_gain * a_xy;
      if (options_.opposition_gain * a_n > options_.max_opposition_speed)
        v_op = a_xy * (options_.max_opposition_speed / a_n);
      ff.template head<3>() = v_op + R_FL.col(2) * lo.velocity[2];
    }
    fo.velocity += ff;
    if (!lo.velocity.allFinite() || !fo.velocity.allFinite()) {
      arms_ = backup;
      return Status::numerical_failure;
    }
    feedforward_ = ff;
    leader_out = lo;
    follower_out = fo;
    return Status::ok;
  }

  /// New reference sensor poses X_fs' for both arms (DualArmPushing::setReferences).
  Status setReferences(const Group& leader_reference, const Group& follower_reference) noexcept {
    return arms_.setReferences(leader_reference, follower_reference);
  }
  /// Clears both controllers, both filters and the last feedforward (options kept).
  void reset() noexcept {
    arms_.reset();
    feedforward_.setZero();
  }

  bool terminated() const noexcept { return arms_.terminated(); }  ///< whether the leader has reached the target (latched)
  /// The centralised part of the follower's last twist, u_ff, in its sensor frame.
  const Tangent& followerFeedforward() const noexcept { return feedforward_; }
  const Arms& arms() const noexcept { return arms_; }  ///< the decentralised pair it extends
  const typename Arms::Leader& leader() const noexcept { return arms_.leader(); }  ///< the leader's controller
  const typename Arms::Follower& follower() const noexcept { return arms_.follower(); }  ///< the follower's controller
  const Options& options() const noexcept { return options_; }  ///< the options in force

 private:
  friend class Configurable<CentralisedDualArmPushing>;
  Status apply(const Options& options) noexcept {  // validated (Configurable)
    if (const Status a = arms_.configure(options.arms); a != Status::ok) return a;
    options_ = options;
    return Status::ok;
  }

  Arms arms_{};
  Options options_{};
  Tangent feedforward_ = Tangent::Zero();
};

/// The paper's dual-arm presets (dualArmPushingPreset: Table 8 leader, Table 9 follower, the
/// tall-object offsets when `tall_object`) with the centralised follower's defaults: the push
/// feedforward, no opposition gain (Options::opposition_gain), and a 20 mm/s limit on the
/// opposition velocity for a caller who sets one (above the leader's 15 mm/s alignment clip).
template <class Scalar, class Filter = DiscriminativeBayesFilter<SE3<Scalar>>>
typename CentralisedDualArmPushing<SE3<Scalar>, Filter>::Options centralisedDualArmPushingPreset(
    bool tall_object = false, const PaperGainConvention& c = {}) {
  typename CentralisedDualArmPushing<SE3<Scalar>, Filter>::Options o;
  o.arms = dualArmPushingPreset<Scalar, Filter>(tall_object, c);
  return o;
}

}  // namespace lieservo

#include <lieservo/detail/options_pop.hpp>

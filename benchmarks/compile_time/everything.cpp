// Compile-time unit 3 (benchmarks/compile_time.py): everything in lieservo.hpp instantiated for
// SE(3) in double and float (explicit instantiation: every member of every class template).
#include <lieservo/lieservo.hpp>
#include <lieservo/realtime.hpp>

namespace lieservo {

#define LIESERVO_INSTANTIATE_ALL(S)                                            \
  template class SO3<S>;                                                       \
  template class SE3<S>;                                                       \
  template struct ConcentratedGaussian<SE3<S>>;                                \
  template class DiscriminativeBayesFilter<SE3<S>>;                            \
  template class MimoPid<S, 6>;                                                \
  template class TactileServoController<SE3<S>>;                               \
  template class PushingController<SE3<S>>;                                    \
  template class TactileLoop<TactileServoController<SE3<S>>>;                  \
  template class TactileLoop<PushingController<SE3<S>>>;                       \
  template class DualArmPushing<SE3<S>>;                                       \
  template class CentralisedDualArmPushing<SE3<S>>;                            \
  template class realtime::VelocitySmoother<S>;                                \
  template Status fuse<DefaultJacobian, SE3<S>>(const ConcentratedGaussian<SE3<S>>&,        \
                                               const ConcentratedGaussian<SE3<S>>&,        \
                                               const FusionOptions<S>&, FusionResult<SE3<S>>&); \
  template Status fromTangentGaussian<DefaultJacobian, SE3<S>>(const SE3<S>::Tangent&,      \
                                                              const SE3<S>::Tangent&,      \
                                                              ConcentratedGaussian<SE3<S>>&);

LIESERVO_INSTANTIATE_ALL(double)
LIESERVO_INSTANTIATE_ALL(float)

template class realtime::LatestValueChannel<realtime::TwistCommand>;

}  // namespace lieservo

int main() { return 0; }

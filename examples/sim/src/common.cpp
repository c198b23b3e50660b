// Scene-parameter checks shared by the simulation module (see lieservo_sim/common.hpp).
#include "lieservo_sim/common.hpp"

#include <cmath>
#include <sstream>

namespace lieservo::sim {

void requirePositive(double v, const char* name) {
  if (!(std::isfinite(v) && v > 0)) {
    std::ostringstream s;
    s << name << " must be finite and > 0 (got " << v << ")";
    throw SceneError(s.str());
  }
}
void requireNonNegative(double v, const char* name) {
  if (!(std::isfinite(v) && v >= 0)) {
    std::ostringstream s;
    s << name << " must be finite and >= 0 (got " << v << ")";
    throw SceneError(s.str());
  }
}
void requireValidPose(const SE3d& X, const char* name) {
  const Mat3 R = X.rotationMatrix();
  if (!X.allFinite()) throw SceneError(std::string(name) + " has a non-finite entry");
  if ((R.transpose() * R - Mat3::Identity()).norm() > 1e-6 || R.determinant() < 0)
    throw SceneError(std::string(name) + " rotation is not orthonormal with det +1");
}

}  // namespace lieservo::sim

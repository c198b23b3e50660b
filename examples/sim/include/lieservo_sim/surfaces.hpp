// lieservo_sim/surfaces.hpp — rigid surface geometry for the contact model.
//
// Every surface is described in its own object frame {o}.  closest(q) returns the surface
// point nearest to q, the outward unit normal there and the signed distance of q (positive
// outside the solid).  The hemispherical sensor tip of radius R with centre c touches the
// surface when signed_distance(c) < R; the contact depth is R − signed_distance(c).
//
//  PlaneSurface     z_o = 0, solid below (z_o < 0), outward normal +z_o.
//  SphereSurface    a dome: sphere of radius a centred at the origin (upper half used).
//  RampSurface      a curved ramp extruded along x_o: height h(y) = H for y < 0,
//                   H (1 + cos(π y / L)) / 2 for 0 ≤ y ≤ L, 0 for y > L (convex, then concave).
//  PrismSurface     a vertical prism (extruded along z_o) with a convex polygonal or circular
//                   cross-section centred on the origin (the pushed objects); only the side
//                   faces take part in contact (the tip stays between floor and top).
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "common.hpp"

namespace lieservo::sim {

struct SurfacePoint {
  Vec3 point = Vec3::Zero();    ///< nearest surface point (object frame)
  Vec3 normal = Vec3::UnitZ();  ///< outward unit normal at `point`
  double signed_distance = 0;   ///< of the query point; > 0 outside the solid
};

class Surface {
 public:
  virtual ~Surface() = default;
  virtual SurfacePoint closest(const Vec3& q) const = 0;
  virtual std::string name() const = 0;
  /// Polylines (object frame) that draw the object in the plots.
  virtual std::vector<std::vector<Vec3>> outline() const = 0;
};

class PlaneSurface final : public Surface {
 public:
  /// half_extent: half the side of the drawn square plate (mm).
  explicit PlaneSurface(double half_extent = 60);
  SurfacePoint closest(const Vec3& q) const override;
  std::string name() const override { return "plane"; }
  std::vector<std::vector<Vec3>> outline() const override;

 private:
  double half_;
};

class SphereSurface final : public Surface {
 public:
  explicit SphereSurface(double radius);
  SurfacePoint closest(const Vec3& q) const override;
  std::string name() const override { return "dome"; }
  std::vector<std::vector<Vec3>> outline() const override;
  double radius() const { return a_; }

 private:
  double a_;
};

class RampSurface final : public Surface {
 public:
  /// height H, curved length L (along y_o), width W (along x_o, for the drawing).
  RampSurface(double height, double length, double width = 80);
  SurfacePoint closest(const Vec3& q) const override;
  std::string name() const override { return "curved_ramp"; }
  std::vector<std::vector<Vec3>> outline() const override;
  double height(double y) const;
  double slope(double y) const;
  double curvature2(double y) const;  ///< h''(y)
  double length() const { return L_; }
  double heightMax() const { return H_; }

 private:
  double H_, L_, W_;
};

class PrismSurface final : public Surface {
 public:
  /// Convex polygon (counter-clockwise, object xy, centred on its centre of mass).
  static PrismSurface polygon(std::vector<Vec2> vertices_ccw, double height, std::string name);
  static PrismSurface square(double side, double height, std::string name);
  static PrismSurface regularPolygon(int sides, double circumradius, double height, std::string name);
  static PrismSurface circle(double radius, double height, std::string name);

  SurfacePoint closest(const Vec3& q) const override;
  std::string name() const override { return name_; }
  std::vector<std::vector<Vec3>> outline() const override;
  /// Planar part of closest(): nearest boundary point and outward normal of a 2-D point.
  SurfacePoint closest2d(const Vec2& q) const;
  bool isCircle() const { return radius_ > 0; }
  double height() const { return height_; }
  const std::vector<Vec2>& vertices() const { return vertices_; }
  /// Ratio c = m_max / f_max of the ellipsoidal limit surface for a uniform pressure
  /// distribution over the footprint (mean distance of the footprint from the centre), mm.
  double uniformPressureLimitSurfaceRatio() const;
  /// Largest distance of the boundary from the centre (for plotting / bounds), mm.
  double circumradius() const;

 private:
  PrismSurface() = default;
  std::vector<Vec2> vertices_;
  double radius_ = 0;  // > 0: circle
  double height_ = 0;
  std::string name_;
};

}  // namespace lieservo::sim

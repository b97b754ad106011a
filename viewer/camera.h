// Camera: a trackball around the model's bounding sphere.
//
// The model is centred at the origin and scaled to unit radius before the camera
// sees it (Renderer does that from the bounds it is given), so the camera only
// stores a rotation, a zoom and a pan, and the same camera serves both panes of the
// split view: the original and the level of detail then have the same projected
// size, as in the paper's Figures 8-10.
#pragma once

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <string>

namespace viewer {

enum class View { Front, Side, Top, Iso };

/// Parses "front", "side", "top" or "iso"; false for anything else.
inline bool parseView(const std::string& s, View& v) {
  if (s == "front")
    v = View::Front;
  else if (s == "side")
    v = View::Side;
  else if (s == "top")
    v = View::Top;
  else if (s == "iso")
    v = View::Iso;
  else
    return false;
  return true;
}

struct Camera {
  Eigen::Quaternionf rotation = Eigen::Quaternionf::Identity();
  float distance = 2.8f;  ///< eye distance in model radii: the model nearly fills the height
  Eigen::Vector2f pan = Eigen::Vector2f::Zero();
  float fovYDegrees = 40.0f;

  /// Standard views of a model whose +Z is its front (the bundled head looks down +Z).
  void setView(View v) {
    using Eigen::AngleAxisf;
    using Eigen::Vector3f;
    const float pi = 3.14159265f;
    pan.setZero();
    distance = 2.8f;
    switch (v) {
      case View::Front:
        rotation = Eigen::Quaternionf::Identity();
        break;
      case View::Side:
        rotation = AngleAxisf(-pi / 2, Vector3f::UnitY());
        break;
      case View::Top:
        rotation = AngleAxisf(pi / 2, Vector3f::UnitX());
        break;
      case View::Iso:
        rotation = AngleAxisf(0.45f, Vector3f::UnitX()) * AngleAxisf(-pi / 4, Vector3f::UnitY());
        break;
    }
  }

  /// Rotates by the arcball drag between two points in normalised window coordinates
  /// ([-1, 1]^2, y up): each point is lifted onto a unit sphere (or the hyperbolic
  /// sheet outside it, so the rotation stays continuous at the rim), and the rotation
  /// takes the first lifted point to the second.
  void drag(const Eigen::Vector2f& from, const Eigen::Vector2f& to) {
    const Eigen::Vector3f a = lift(from), b = lift(to);
    const Eigen::Quaternionf q = Eigen::Quaternionf::FromTwoVectors(a, b);
    rotation = (q * rotation).normalized();
  }

  void zoom(float steps) { distance = std::clamp(distance * std::pow(0.9f, steps), 1.05f, 50.0f); }

  /// World-to-eye transform of the unit-radius model.
  Eigen::Matrix4f viewMatrix() const {
    Eigen::Affine3f t = Eigen::Affine3f::Identity();
    t.translate(Eigen::Vector3f(pan.x(), pan.y(), -distance));
    t.rotate(rotation);
    return t.matrix();
  }

  Eigen::Matrix4f projection(float aspect) const {
    const float n = std::max(0.01f, distance - 1.5f), f = distance + 1.5f;
    const float t = 1.0f / std::tan(fovYDegrees * 3.14159265f / 360.0f);
    Eigen::Matrix4f p = Eigen::Matrix4f::Zero();
    p(0, 0) = t / aspect;
    p(1, 1) = t;
    p(2, 2) = -(f + n) / (f - n);
    p(2, 3) = -2.0f * f * n / (f - n);
    p(3, 2) = -1.0f;
    return p;
  }

 private:
  static Eigen::Vector3f lift(const Eigen::Vector2f& p) {
    const float r2 = p.squaredNorm();
    const float z = r2 <= 0.5f ? std::sqrt(1.0f - r2) : 0.5f / std::sqrt(r2);
    return Eigen::Vector3f(p.x(), p.y(), z).normalized();
  }
};

}  // namespace viewer

// Camera's bodies live here, out of the header that every viewer file includes.
#include "camera.h"

#include <algorithm>
#include <cmath>

namespace viewer {

namespace {

// Lifts a point of the window onto the unit sphere, or onto the hyperbolic sheet
// outside it, so that the rotation stays continuous at the rim.
Eigen::Vector3f lift(const Eigen::Vector2f& p) {
  const float r2 = p.squaredNorm();
  const float z = r2 <= 0.5f ? std::sqrt(1.0f - r2) : 0.5f / std::sqrt(r2);
  return Eigen::Vector3f(p.x(), p.y(), z).normalized();
}

}  // namespace

void Camera::setView(View v) {
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

void Camera::drag(const Eigen::Vector2f& from, const Eigen::Vector2f& to) {
  // The rotation taking a to b: half the angle between them about a x b, as the
  // quaternion (1 + a.b, a x b) up to scale, which the normalisation of the product
  // removes. Both lifted points have z > 0, so they are never opposite (where the axis
  // would be undefined); Quaternion::FromTwoVectors handles that case with an SVD that
  // cost every file including it ten seconds of compilation.
  const Eigen::Vector3f a = lift(from), b = lift(to), axis = a.cross(b);
  const Eigen::Quaternionf q(1.0f + a.dot(b), axis.x(), axis.y(), axis.z());
  rotation = (q * rotation).normalized();
}

void Camera::zoom(float steps) {
  distance = std::clamp(distance * std::pow(0.9f, steps), 1.05f, 50.0f);
}

Eigen::Matrix4f Camera::viewMatrix() const {
  Eigen::Affine3f t = Eigen::Affine3f::Identity();
  t.translate(Eigen::Vector3f(pan.x(), pan.y(), -distance));
  t.rotate(rotation);
  return t.matrix();
}

Eigen::Matrix4f Camera::projection(float aspect) const {
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

}  // namespace viewer

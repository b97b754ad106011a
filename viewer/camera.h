// Camera: a trackball around the model's bounding sphere.
//
// The model is centred at the origin and scaled to unit radius before the camera
// sees it (Renderer does that from the bounds it is given), so the camera only
// stores a rotation, a zoom and a pan, and the same camera serves both panes of the
// split view: the original and the level of detail then have the same projected
// size, as in the paper's Figures 8-10.
#pragma once

#include <Eigen/Geometry>
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
  void setView(View v);

  /// Rotates by the arcball drag between two points in normalised window coordinates
  /// ([-1, 1]^2, y up): each point is lifted onto a unit sphere (or the hyperbolic
  /// sheet outside it, so the rotation stays continuous at the rim), and the rotation
  /// takes the first lifted point to the second.
  void drag(const Eigen::Vector2f& from, const Eigen::Vector2f& to);

  void zoom(float steps);

  /// World-to-eye transform of the unit-radius model.
  Eigen::Matrix4f viewMatrix() const;

  Eigen::Matrix4f projection(float aspect) const;
};

}  // namespace viewer

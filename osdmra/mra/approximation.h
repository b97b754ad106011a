// Approximation: a truncated wavelet expansion as a renderable, crack-free mesh.
//
// Given a decomposition, keep a prefix of one order of the coefficients (selection.h:
// error removed per triangle added, or importance alone; truncation.h ranks them),
// build the adaptive level-of-detail connectivity (lod.h), and place every vertex on
// the truncated surface at its parameter point (math.md 5, paper section 4):
//   polyhedral: the truncated reconstruction's values (the surface interpolates them);
//   Loop: exact limit positions and limit normals through OpenSubdiv's limit stencils;
// or, optionally, at the mesh's least-squares fit of the full surface (placement.h).
// The Approximator holds what every extraction reuses (the order and the triangle
// count of each of its prefixes, limit stencils, the full-resolution reference), so a
// new level of detail costs one synthesis plus work proportional to the output (plus
// one walk of M^J and a sparse solve with the fit).
#pragma once

#include <memory>
#include <mutex>
#include <vector>

#include "osdmra/mra/decomposition.h"
#include "osdmra/mra/filter_bank.h"
#include "osdmra/mra/lod.h"
#include "osdmra/mra/placement.h"
#include "osdmra/mra/selection.h"
#include "osdmra/mra/truncation.h"

namespace osdmra {

struct Approximation {
  TriMesh mesh;            ///< vertices on the truncated surface; normals for Loop
  LodMesh lod;             ///< the same faces in hierarchy (level-J) vertex indices
  long long selected = 0;  ///< coefficients the criterion chose (count, epsilon, budget)
  long long kept = 0;      ///< coefficients kept: `selected` plus the free ones
  long long total = 0;     ///< coefficients in the decomposition
  KeepMask keep;           ///< which ones are kept
  int triangles() const { return static_cast<int>(mesh.F.rows()); }
};

struct ApproximationOptions {
  /// How coefficients are ranked: keepAbove compares it with epsilon, and the
  /// orders of keepCount, keepFraction and budget are built from it.
  Importance importance = Importance::Scaled;
  /// The order keepCount, keepFraction and budget take prefixes of (selection.h):
  /// error removed per triangle added (default), or importance alone.
  Selection selection = Selection::RateDistortion;
  /// Measure importance in the surface's own metric (surfaceAreaWeights): regions the
  /// parameterisation shrinks count by their area on the surface. Off: the paper's
  /// inner product, every base triangle of area 1.
  bool surfaceMetric = false;
  /// Also keep the free coefficients (saturate()): those whose vertex the mesh has
  /// anyway, inside the refined region. The mesh is the same, its vertices sit on a
  /// closer truncated surface (at the 5% budget of the semi-regular head in
  /// docs/BENCHMARKS.md, 18% lower sampled RMS error). Off: exactly the selection.
  bool saturate = true;
  /// Where the vertices go (placement.h): on the truncated surface, or the mesh's
  /// least-squares fit of the full-resolution surface (one sparse solve per
  /// extraction).
  Placement placement = Placement::Surface;
  FitOptions fit;
  /// The surface Placement::Closest and Placement::Levels match the level of detail to;
  /// null: the full-resolution surface (fullResolution()). A surface that is a
  /// remeshing of some input is measured against that input: matching to it instead
  /// leaves out the remeshing's own error (lodForBudget gives it). It is matched at
  /// its vertices and at as many area samples of it as the full-resolution surface has
  /// vertices (ClosestTarget).
  std::shared_ptr<const TriMesh> closestTarget;
};

class Approximator {
 public:
  /// `bank` and `d` (made with that bank) must outlive the approximator.
  Approximator(const FilterBank& bank, const Decomposition& d, ApproximationOptions options = {});

  long long numCoefficients() const { return static_cast<long long>(order_.size()); }

  /// The first `count` coefficients of the selection order.
  Approximation keepCount(long long count) const;
  /// A fraction in [0, 1] of the coefficients, the first ones of the selection order.
  Approximation keepFraction(double fraction) const;
  /// Every coefficient of importance at least `epsilon`.
  Approximation keepAbove(double epsilon) const;
  /// The most coefficients whose mesh has at most `triangles` faces. Never fewer
  /// triangles than the base mesh has. The first call computes triangleCounts().
  Approximation budget(long long triangles) const;
  /// Entry k: the triangle count when the first k coefficients of the order are kept
  /// (lodTriangleCounts), computed once, on first use (thread-safe).
  const std::vector<long long>& triangleCounts() const;
  /// Does now the one-time work that Placement::Levels otherwise does on the first
  /// extraction that needs it (the closest fit of each level's uniform mesh, about a
  /// second per level on a 307,200-face remesh); nothing for the other placements.
  /// Thread-safe.
  void prepare() const;

  /// The full-resolution surface the approximations are compared with: M^J with the
  /// input's positions (polyhedral) or their limit points and normals (Loop).
  const TriMesh& fullResolution() const { return full_; }
  /// The exact parametric L2 distance between an approximation's truncated surface and
  /// the full one (math.md 5; the square summed over x, y, z).
  double l2Error(const Approximation& a) const;

 private:
  KeepMask maskOfCount(long long count) const;
  Approximation make(const KeepMask& keep) const;
  Points positions(const Points& controls, Points* normals) const;
  // Placement::Levels: the closest fit of the uniform M^j, made on first use.
  const Points& levelFit(int j) const;
  void placeByLevels(Approximation& a) const;

  const FilterBank& bank_;
  const Decomposition& d_;
  ApproximationOptions options_;
  std::vector<Eigen::VectorXd> importance_;
  CoefficientOrder order_;  // options_.selection's order
  std::unique_ptr<Hierarchy::LimitStencils> limit_;
  Points fullControls_;  // c^J
  TriMesh full_;
  std::unique_ptr<ClosestTarget> closestTarget_;  ///< for Closest and Levels
  mutable std::vector<Points> levelFits_;         ///< Levels: per level j < J, n_j x 3
  mutable std::unique_ptr<std::once_flag[]> levelOnce_;
  mutable std::once_flag countsOnce_;
  mutable std::vector<long long> counts_;
  mutable std::once_flag l2Once_;
  mutable std::unique_ptr<L2Distance> l2_;  // made on the first l2Error
};

}  // namespace osdmra

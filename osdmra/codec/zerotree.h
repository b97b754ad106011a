// The edge zerotree: successive-refinement coding of quantised wavelet coefficients
// over the parent-child structure of the subdivision hierarchy.
//
// Coefficient (j, e) sits on edge e of M^j (at the new vertex n_j + e of M^{j+1}).
// Its children are the level-(j+1) coefficients on the edges that refine it
// (Khodakovsky, Schroder and Sweldens, "Progressive Geometry Compression", SIGGRAPH
// 2000, section 4.2): the two halves of e, and in each triangle beside e the edge of
// the central child triangle parallel to e. An interior edge has four children, a
// boundary edge three; the coefficients of the last level have none. The trees are
// rooted at the edges of the base mesh. Each of the three components of a
// coefficient (normal, along, across; local_frames.h) has its own tree.
//
// Coding is by bit planes, most significant first, as in SPIHT (Said and Pearlman,
// 1996). For plane p (threshold 2^p):
//   sorting pass     level by level, coarse to fine, every reached node that is not
//                    yet significant codes "|q| >= 2^p" (and then its sign), and
//                    every reached node whose subtree is not yet known to hold a
//                    significant node codes "some descendant has |q| >= 2^p"; a yes
//                    reaches its children, which the same pass visits next level;
//   refinement pass  every node significant before this plane codes bit p of |q|.
// Roots are always reached. One "no" for a subtree stands for all of it: the zeros
// of smooth regions at fine levels cost almost nothing. Every decision is coded by
// the range coder (range_coder.h) in a context of its kind, level and component,
// and of what is already known nearby: the parent's significance, how many of the
// edges beside it in its triangles are significant (or have significant subtrees),
// and for tangential components the significance of the normal one, as context
// modelling does for image wavelets (Taubman's EBCOT, 2000). A sign is coded in the
// context of the signs of the significant edges beside it and of its parent: along a
// crease or over a curved region neighbours share the sign of their normal
// components (on spot's J = 5 remesh, +0.1 to +1.5 dB at 1.5-3 bits per vertex; on
// the bundled head, where Loop's details show no such pattern, the same to 0.03 dB).
//
// Truncation: the decoder updates its state only once a whole event is decoded (a
// significance bit and its sign, a subtree bit, a refinement bit), so a cut stream
// leaves a consistent state: every node knows an interval for its |q|.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "osdmra/codec/range_coder.h"
#include "osdmra/subdivision/hierarchy.h"

namespace osdmra {

/// Children of every coefficient: children[j][e] for j = 0..J-2 lists the edges of
/// M^{j+1} refining edge e of M^j (-1 for a missing fourth child on a boundary).
struct EdgeTree {
  std::vector<int> edges;  ///< E_j, the coefficient count of level j = 0..J-1
  std::vector<std::vector<std::array<int, 4>>> children;
  /// neighbours[j][e]: the other edges of the triangles of M^j beside edge e (-1 for
  /// the missing two on a boundary); their state is the coder's spatial context.
  std::vector<std::vector<std::array<int, 4>>> neighbours;
};

/// The edge tree of a hierarchy, from its face and midpoint conventions alone.
EdgeTree edgeTree(const Hierarchy& h);

/// Signed integer coefficients per level: q[j][3 e + c] for component c of edge e.
using QuantisedLevels = std::vector<std::vector<std::int32_t>>;

/// The largest |q| must stay below 2^kMaxPlanes.
constexpr int kMaxPlanes = 30;

/// Highest plane with a significant coefficient: floor(log2(max |q|)), or -1 when
/// every coefficient is 0.
int topPlane(const QuantisedLevels& q);

/// Codes `q` (shaped like `tree`) plane by plane from `top` down to plane 0.
void encodeZerotree(const EdgeTree& tree, const QuantisedLevels& q, int top, RangeEncoder& enc);

/// What a decoder knows of every coefficient: reconstruct() turns it into values.
struct ZerotreeState {
  std::vector<std::vector<std::int32_t>> high;  ///< the known leading bits of |q|
  std::vector<std::vector<std::int8_t>> plane;  ///< lowest plane known; -1: insignificant
  std::vector<std::vector<std::int8_t>> sign;   ///< +1 or -1 once significant
  int planesDone = 0;                           ///< planes decoded completely
  bool complete = false;                        ///< every plane down to 0 decoded
};

/// Decodes what `dec` determines of a stream encodeZerotree wrote for the same tree
/// and top plane; a cut stream gives the state at the last complete event.
ZerotreeState decodeZerotree(const EdgeTree& tree, int top, RangeDecoder& dec);

/// Each coefficient's best value in units of the quantisation step: 0 while
/// insignificant, else the middle of the interval its known bits leave, (|q| + 1/2)
/// once every plane is known. reconstruct(decodeZerotree(...))[j][i] is within 1 of
/// q[j][i] for a complete stream (within 1/2 when q != 0). The middle, not nearer 0 as
/// for a Laplacian source: 3/8 of the interval for coefficients just significant (and
/// 1/2 for the others) moved the head's PSNR by -0.06 to +0.07 dB at 0.5-10 bits per
/// vertex, 3/8 for all cut coefficients lost 0.1-0.4 dB (2026-12-03).
std::vector<std::vector<double>> reconstruct(const ZerotreeState& s);

/// The value reconstruct() gives a coefficient q that every plane codes.
inline double reconstructed(std::int32_t q) {
  return q == 0 ? 0.0 : q > 0 ? q + 0.5 : q - 0.5;
}

}  // namespace osdmra

// osdmra: the command-line front end. Thin: every computation is a library call
// through the pipeline (osdmra/pipeline.h); this file holds the usage and the
// dispatch to the commands, which live by family in mesh_commands.cpp,
// analysis_commands.cpp, lod_commands.cpp and codec_commands.cpp. Errors are osdmra::Error from
// anywhere below, printed as "osdmra: <message>" with exit 1, the library's option
// names replaced by this tool's flags.
#include <iostream>
#include <new>

#include "allocator.h"
#include "args.h"
#include "commands.h"
#include "osdmra/base/error.h"

namespace osdmra::cli {
namespace {

const char* kUsage = R"(osdmra: wavelet multiresolution analysis of subdivision surfaces
(Lounsbery, DeRose and Warren 1993) on OpenSubdiv.

usage: osdmra <command> [options]

commands:
  info IN                      topology of a mesh, and its subdivision connectivity
                               (levels, base mesh) found from connectivity alone
  subdivide BASE --levels J -o OUT [--scheme loop|linear] [--displace A --seed N]
                               refine a base mesh J times (a test surface when
                               displaced by noise at every level)
  analyze IN -o OUT.mra [--levels J] [--scheme loop|linear]
                 [--wavelets lazy|quasi|pre|fixed] [--rings R] [--remesh ...]
                               decompose a surface with subdivision connectivity (any
                               vertex and face order) into base mesh + wavelet details;
                               any other mesh with --remesh [--base-faces N] (then
                               --levels J is the remesh's; see remesh)
  synthesize IN.mra -o OUT [--level j] [--keep F | --epsilon E] [--importance scaled|plain]
                               rebuild the surface (or its level-j approximation),
                               optionally from the most important coefficients only
  lod IN (--epsilon E | --budget N | --keep F) -o OUT [--scheme S] [--rings R]
                 [--importance scaled|plain] [--selection rd|importance] [--exact]
                 [--placement surface|fit|closest|levels] [--metric domain|surface]
                 [--samples N --seed S]
                               crack-free adaptive mesh from the coefficients that
                               remove the most error per triangle added (rd, the
                               default; importance: the most important ones, as in
                               the paper), with its errors; the coefficients of
                               vertices the mesh has anyway are kept too (no extra
                               triangle) unless --exact. Defaults: the polyhedral
                               scheme (--scheme linear; loop: limit positions and
                               normals) and --placement closest: the least-squares
                               fit of the full surface, then the two surfaces
                               matched both ways (eight rounds, a few seconds on
                               300,000 faces); surface: on the truncated surface
                               (the paper; fastest), fit: the fit alone, levels:
                               the matching made once per level and looked up
                               (re-extraction as fast as surface: the viewer,
                               sweep's default); --metric surface weighs importance
                               by area on the surface, not on the base domain;
                               --remesh as for analyze, eight times with a
                               budget: over a base of the budget (five times:
                               as asked; with long thin faces where the input
                               is flat across them; with those and its edges
                               flipped where that fits the input better; the
                               first two again with the input's vertices
                               removed in order of the error each removal
                               makes), a half, a quarter and a
                               sixteenth of it (and the input's own
                               hierarchy cut, where it has one), each matched
                               to the input itself (closest, levels), the level
                               of detail closest to the input kept (all reported),
                               unless --base-faces says otherwise (each
                               with as many levels, up to 5, as keep the remeshing
                               within 2^19 faces, unless --levels); the remeshing
                               and the level of detail's distance to the input as
                               given are reported apart; lod and sweep remesh
                               with --stages vertex --retriangulation error
                               (see remesh)
  remesh IN --base-faces N --levels J -o OUT [--feature-angle A]
                 [--min-component-faces F] [--max-faces M] [--smoothing-sweeps S]
                 [--stages auto|vertex|mesh] [--retriangulation shape|error]
                 [--skinny-where-flat F] [--cap-angle A] [--base-splits on|off]
                 [--grid-refinement on|off]
                               any manifold triangle mesh (any genus, boundaries) to
                               subdivision connectivity: a base of about N faces
                               (default 300) split J times (default 5), positions
                               on the input; reports the distance to the input and
                               any flipped, zero-area or crossing triangles left,
                               with a warning on stderr (and in the JSON) if any
                               are, if the result is over 1% of the diagonal from
                               the input somewhere, or if the base has more faces
                               than asked (it keeps tips of protrusions and
                               feature lines, but drops lines on their own
                               shorter than a base edge where the base would
                               be over size); components of fewer than F faces
                               are dropped first
                               (default 0: all kept); with --max-faces, a base
                               larger than asked is split fewer times, keeping the
                               output within M faces; S sweeps (default 10, 0:
                               none) lower the parameterisation's stretch first;
                               --stages vertex relaxes the simplification's
                               limits vertex by vertex, for those passed over for
                               more important ones (a base closer to the input,
                               a more distorted map), mesh mesh-wide; default
                               auto: vertex, and mesh as well where that leaves
                               defects, the one with fewer kept;
                               --retriangulation error fills each removed
                               vertex's ring by the error made, as a quadric
                               simplifier would (default shape: by the faces'
                               shape first); --skinny-where-flat F lets base
                               faces go under the stages' angle bounds, down to
                               1 degree, where the input points each holds lie
                               within F of its width from its plane (default 0:
                               never; lod --remesh --budget tries the whole
                               budget a second time with F = 0.1, none if 0);
                               --cap-angle A flips a base edge opposite an
                               angle over A degrees where the grid sampled
                               over the two faces folds less so (default 90,
                               0: no flips); where the grid still folds through
                               both maps, the faces holding its folds are split,
                               within 10% of N, and kept where it folds less;
                               where the base is over N anyway and defects are
                               left, within 10% of the base made, and kept where
                               fewer are left (--base-splits off: never; lod
                               --remesh --budget never splits); each base
                               face's grid is made level by level in its
                               domain, a point of a triangle that would fold
                               stepped where it folds fewer, the map kept a
                               bijection (--grid-refinement off: the uniform
                               grid);
                               --samples N: samples a side of the distance to
                               the input it reports (default 100000)
  sweep IN --csv OUT.csv [--plot OUT.png] [--points K] [lod's options]
                               error against triangle count over the whole range
                               (lod's defaults but --placement levels)
  mask IN --level j --vertex i [--scheme loop|linear]
                               subdivision and inner-product masks around a vertex
                               of level j over the base mesh IN (paper, Fig. 4, 5)
  orthogonality BASE --level j [--scheme S] [--max-rings R]
                               how close lazy, quasi (r = 0..R), fixed and pre-wavelets
                               of level j over BASE are to orthogonal
  shape NAME -o OUT            write a built-in base mesh (tetrahedron, octahedron,
                               icosahedron, torus, genus2, genus3, disc, cylinder,
                               valences)
  compress IN -o OUT.osz [--psnr P | --bits-per-vertex B | --bytes N] [--scheme S]
                 [--wavelets W] [--rings R] [--psnr-measure surface|vertices]
                 [--precision E] [--tangent-weight W] [--tangent-floor F]
                 [--bend-gain K] [--level-gain G] [--samples N --seed S] [--remesh ...]
                               progressive wavelet compression (edge zerotrees of the
                               coefficients in local frames, range coded): cut at a
                               PSNR (dB, 20 log10(diagonal / RMS), RMS of the sampled
                               surface distance, or of corresponding vertices with
                               --psnr-measure vertices; N samples a side, default
                               100000), a size in bits per vertex or
                               bytes, or whole (the finest step is E times the
                               diagonal, default 1e-5); any other manifold mesh with
                               --remesh as for analyze; wavelets fixed by default
                               (quasi-wavelets' weights of the regular lattice: no
                               solve when decoding), or W = quasi (with --rings), lazy;
                               scheme S loop or linear, by default the one whose stream
                               is better at the rate asked (the closer at a size, the
                               shorter at a PSNR, the shorter whole stream otherwise):
                               linear on remeshes of scans, flat in each input triangle;
                               tangential components weighted by the surface's bend,
                               clamp(K bend, F, W), defaults 0.5, 1/16, 0.25
  decompress IN.osz -o OUT [--bytes N]
                               decode the stream, or only its first N bytes (every
                               prefix holding the header and base mesh decodes)
  demo [IN] [--out DIR] [--remesh ...]
                               the paper's example on the bundled scanned head (or IN,
                               remeshed first with --remesh as for analyze): analyse
                               and rebuild it, levels of detail of 4,054, 12,310 and
                               16,098 triangles, their errors, error-against-triangles
                               sweeps and plots, all written to DIR (default out/)

common options:
  --json        print a JSON summary on stdout instead of text
  --progress    report progress on stderr (default when stderr is a terminal)
  --quiet       no progress
  -h, --help    help for a command

Meshes: .obj, .off, .ply (ascii or binary). Errors name the file, the line or
element, and what is wrong; the exit status is then 1 and no output is written.
)";

int dispatch(int argc, char** argv) {
  if (argc < 2) {
    std::cerr << kUsage;
    return 2;
  }
  const std::string command = argv[1];
  std::vector<std::string> rest(argv + 2, argv + argc);
  for (const std::string& a : rest)
    if (a == "--help" || a == "-h") {
      std::cout << kUsage;
      return 0;
    }
  if (command == "--help" || command == "-h" || command == "help") {
    std::cout << kUsage;
    return 0;
  }
  if (command == "--version") {
    std::cout << "osdmra 0.1.0\n";
    return 0;
  }
  if (command == "info") return cmdInfo(rest);
  if (command == "subdivide") return cmdSubdivide(rest);
  if (command == "analyze") return cmdAnalyze(rest);
  if (command == "synthesize") return cmdSynthesize(rest);
  if (command == "mask") return cmdMask(rest);
  if (command == "lod") return cmdLod(rest);
  if (command == "sweep") return cmdSweep(rest);
  if (command == "orthogonality") return cmdOrthogonality(rest);
  if (command == "shape") return cmdShape(rest);
  if (command == "remesh") return cmdRemesh(rest);
  if (command == "demo") return cmdDemo(rest);
  if (command == "compress") return cmdCompress(rest);
  if (command == "decompress") return cmdDecompress(rest);
  std::cerr << "osdmra: unknown command '" << command << "'\n\n" << kUsage;
  return 2;
}

}  // namespace
}  // namespace osdmra::cli

int main(int argc, char** argv) {
  osdmra::cli::keepFreedMemory();
  try {
    return osdmra::cli::dispatch(argc, argv);
  } catch (const osdmra::Error& e) {
    std::cerr << "osdmra: " << osdmra::cli::withFlagNames(e.what()) << "\n";
  } catch (const std::bad_alloc&) {
    std::cerr << "osdmra: out of memory\n";
  } catch (const std::exception& e) {
    std::cerr << "osdmra: internal error: " << e.what() << "\n";
  }
  return 1;
}

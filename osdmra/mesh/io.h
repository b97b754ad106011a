// Mesh I/O: triangle meshes in Wavefront OBJ, OFF and PLY, in and out, and STL in.
//
// Readers parse one format and nothing more: they reject whatever the format
// itself cannot express for osdmra (polygons other than triangles, indices that
// point nowhere, non-finite coordinates, truncated or corrupt files), but leave the
// topological checks (manifoldness, orientation, isolated vertices) to validate()
// in mesh.h, so a tool can still load a defective mesh to inspect or repair it.
// readValidMesh() does both, which is what front ends normally want.
//
// Every failure is an osdmra::Error whose message starts with the source name and
// says where and what, compiler style:
//   "bunny.obj:1203: face has 4 vertices; osdmra needs triangles"
//   "scan.ply: face 17: vertex index 9001 is out of range (the file has 1200 vertices)"
// Text formats name the line; binary PLY names the element and its index.
//
// The readers are written for hostile input: no input makes them crash, hang or
// allocate much more than the file's own size. Declared element counts are checked
// against the bytes that remain before anything is reserved (when the stream is
// seekable; otherwise storage grows only as data actually arrives).
//
// With ReadOptions::triangulate, polygons are read as fans of triangles instead.
//
// Formats, as read:
//   OBJ  v (x y z, extra w or colour values ignored), vn, f with v, v/t, v/t/n and
//        v//n corners, negative (relative) indices, '\' line continuations. vt and
//        grouping/material statements (g o s usemtl mtllib l p ...) are ignored;
//        free-form geometry and unknown statements are errors.
//   OFF  "OFF" (also COFF, NOFF, STOFF, ... prefixes) with counts on the same or the
//        next line, or no keyword at all; '#' comments; extra per-vertex values
//        (colours, texture coordinates) and per-face colours are ignored.
//   STL  binary (when the size is 84 + 50 n for the n triangles its header declares)
//        or ASCII (solid / facet / outer loop / vertex x3 / endloop / endfacet /
//        endsolid, several solids in a file). A soup of triangles: corners at exactly
//        the same position become one vertex. Facet normals are not read. Not written.
//   PLY  ascii, binary_little_endian and binary_big_endian. Vertex x, y, z (and
//        nx, ny, nz) of any numeric type (char/int8 ... double/float64); the face
//        list vertex_indices (or vertex_index) with any integer count and index
//        types. Other properties and elements, lists included, are skipped.
//
// Normals are advisory: a reader fills TriMesh::N only when the file gives exactly
// one finite normal per vertex (for OBJ: every face corner names a normal and each
// vertex always gets the same one); otherwise N is left empty rather than
// rejecting good geometry.
//
// Writers emit shortest round-trip decimal text (std::to_chars), so text files
// reproduce every double exactly; binary PLY stores doubles. writeMesh() writes to
// a temporary file next to the target and renames it over the target, so an
// interrupted or failed write never leaves a half-written mesh behind.
#pragma once

#include <iosfwd>
#include <string>

#include "osdmra/mesh/mesh.h"

namespace osdmra {

enum class MeshFormat { Obj, Off, Ply, Stl };

/// The format named by the extension of `path`: .obj, .off, .ply or .stl (read only),
/// in any case.
/// Throws Error for any other extension.
MeshFormat meshFormatFromPath(const std::string& path);

/// meshFormatFromPath for a file to be written: also throws Error for .stl, which is
/// read only. Front ends call it before the work whose result they will write.
MeshFormat meshFormatForWriting(const std::string& path);

/// How writePly encodes the data section.
enum class PlyEncoding {
  BinaryLittleEndian,  ///< compact and exact; the default
  Ascii,               ///< human-readable, still exact (shortest round-trip decimals)
};

struct ReadOptions {
  /// Polygons of more than three corners become triangles instead of an error (the
  /// remesher takes quad and polygon meshes so): the fan from the first corner, or
  /// where that folds (a polygon not star-shaped from it, such as an L-shaped face
  /// listed from its end), the polygon's ear clipping in its plane (up to 64 corners).
  /// Off by default: subdivision connectivity is a triangle mesh's, and analysing a
  /// quad mesh as triangles would find none.
  bool triangulate = false;
};

struct WriteOptions {
  PlyEncoding plyEncoding = PlyEncoding::BinaryLittleEndian;
  /// Write TriMesh::N (OBJ vn + f a//a b//b c//c, PLY nx ny nz, OFF as NOFF) when
  /// it has one row per vertex. Set to false to drop normals.
  bool writeNormals = true;
};

// ---- Files -------------------------------------------------------------------

/// Reads the mesh at `path`, format chosen by its extension. Messages name `path`.
/// Does not run validate(): see readValidMesh.
TriMesh readMesh(const std::string& path, const ReadOptions& options = {});

/// readMesh followed by validate(mesh, path): the mesh is a valid subdivision
/// domain (manifold, consistently oriented, no isolated vertices) or this throws.
TriMesh readValidMesh(const std::string& path);

/// Writes `mesh` to `path`, format chosen by its extension. The data goes to a
/// temporary file in the same directory, which then replaces `path` atomically
/// (std::rename); on any failure the temporary file is removed and `path` is left
/// as it was. Throws Error when the mesh has an out-of-range index or a non-finite
/// coordinate (the file would be unreadable) or when the file cannot be written.
void writeMesh(const std::string& path, const TriMesh& mesh, const WriteOptions& opts = {});

// ---- Streams -------------------------------------------------------------------
// `source` is the name used in error messages (a file name, "<stdin>", ...).
// Streams for binary PLY must be opened in binary mode.

TriMesh readMesh(std::istream& in, MeshFormat format, const std::string& source,
                 const ReadOptions& options = {});
TriMesh readObj(std::istream& in, const std::string& source, const ReadOptions& options = {});
TriMesh readOff(std::istream& in, const std::string& source, const ReadOptions& options = {});
TriMesh readPly(std::istream& in, const std::string& source, const ReadOptions& options = {});
TriMesh readStl(std::istream& in, const std::string& source, const ReadOptions& options = {});

/// Writers throw Error on an invalid mesh (see writeMesh) or a failed stream.
void writeMesh(std::ostream& out, MeshFormat format, const TriMesh& mesh,
               const WriteOptions& opts = {});
void writeObj(std::ostream& out, const TriMesh& mesh, const WriteOptions& opts = {});
void writeOff(std::ostream& out, const TriMesh& mesh, const WriteOptions& opts = {});
void writePly(std::ostream& out, const TriMesh& mesh, const WriteOptions& opts = {});

}  // namespace osdmra

// SPDX-License-Identifier: MIT
#pragma once
/// @file view_poly_data.h
/// The vtkPolyData the studio's view draws one primitive with, laid out by slot so that a step
/// (an operation, its undo or redo, described by a PrimitiveChange) updates it in O(change)
/// instead of converting the whole mesh again:
/// - cell i is face slot i, always a triangle; a deleted face is a degenerate cell (all three
///   ids the same point), which draws nothing and is never picked, so cell ids never shift;
/// - with corner normals or UVs, a point per vertex and way of drawing its corners: corners of
///   one vertex share a point while they draw alike (same normal, texture coordinates and morph
///   normal deltas, bit for bit), and split where they differ, as a renderer needs. A mesh
///   with smooth normals and few seams uploads and shades about a point per vertex, not three
///   per face. Without corner normals or UVs, one point per vertex slot, appended and truncated
///   with the mesh.
/// Arrays (as `to_poly_data` names them, so picking and colouring read either): point data
/// "vertex_id", "uv0" (texture coordinates, made the active ones; kept up to date by name, so
/// a viewer may unset them while no texture reads them), "normal" (the posed corner normals,
/// else the mesh's); cell data "face_id". Arrays are filled through their raw storage, in
/// parallel, without per-element virtual calls.

#include <vtkPolyData.h>
#include <vtkSmartPointer.h>
#include <vtkType.h>

#include <cstdint>
#include <memory>
#include <vector>

#include "deepcut/core/model_change.h"
#include "deepcut/core/surface_mesh.h"

namespace deepcut {

struct CornerGroups;
class CornerNormalPoser;

class ViewPolyData {
 private:
  struct Copying;

 public:
  /// The working memory of copying builds (the constructor from a source), sized by the source's
  /// points and the mesh's vertices and faces: kept by a caller that copies again and again (a
  /// view following cuts), each build reuses what the last one allocated instead of touching new
  /// pages. One build at a time; a build reads nothing the last one left in it.
  class CopyScratch {
   public:
    CopyScratch();
    ~CopyScratch();
    CopyScratch(const CopyScratch&) = delete;
    CopyScratch& operator=(const CopyScratch&) = delete;

   private:
    friend class ViewPolyData;
    std::unique_ptr<Copying> copying_;
  };

  /// Converts `mesh` drawn at `positions` (one per vertex slot) with `corner_normals` (one per
  /// corner, e.g. the posed ones; null or empty: the mesh's own normals, if any).
  /// O(vertices + faces), in parallel; the points are the same whatever the thread count. The
  /// corner lists `update` needs are left for `prepare_updates` (the data is drawn without them),
  /// unless a live face names one vertex three times.
  /// @pre (here and in `update`) every live face of `mesh` names vertices below its
  ///      vertex_count (a deleted face's cell is (0, 0, 0) whatever it names).
  /// @pre (here, in `update` and `set_positions`) corner normals are what posing makes of the
  ///      corner's normal, its morph normal deltas and its vertex: corners that share a point
  ///      get equal normals in every pose.
  ViewPolyData(const SurfaceMesh& mesh, const std::vector<glm::vec3>& positions,
               const std::vector<glm::vec3>* corner_normals = nullptr);
  /// The same data as the constructor above given the posed corner normals `posed` makes
  /// (posed_corner_normal.h: those of PosedMesh::corner_normals, bit for bit), each computed
  /// only for the corner a point draws like: one per point, without an array of one per corner
  /// (the studio's first frame after an open, drawn before the scene's corner normals are made).
  /// Corners are grouped as the constructor above groups them (by the mesh's normals and morph
  /// normal deltas, which decide the posed ones). @pre `posed` poses `mesh`'s corners.
  ViewPolyData(const SurfaceMesh& mesh, const std::vector<glm::vec3>& positions,
               const CornerNormalPoser& posed);

  /// The same data as the constructor above (the same points, perhaps numbered otherwise) for a
  /// mesh a step made out of another (a cut's piece, ModelChange::origins): how the corners of
  /// the faces that have a source face (`origin`) share points is taken from `source` (this
  /// class's data drawn for the source mesh as it was before the step, at any pose or positions),
  /// so only the corners of the other faces (the rim) are compared. Streaming passes over the
  /// faces and points instead of comparing every vertex's corners; the corner lists `update`
  /// needs are left for `prepare_updates` (the data is drawn without them). Builds from scratch
  /// when `source` or `origin` does not fit (no corner points, other sizes).
  /// `spare` (data no longer drawn, or null): where the copy fits and `can_take(*spare, slots)`,
  /// its arrays are taken over, so their memory is reused: no new pages to fault in, and the
  /// cells' offsets and face ids (the same for every data) are written only past the spare's
  /// cells; what an array holds past the copy's own room is given back (see `bytes`), and the
  /// spare's corner lists (sized for its corners) are not taken. `spare` is then left without
  /// data, only to be destroyed; otherwise it is untouched.
  /// `scratch` (or null: the build's own): the working memory of the copy, reused.
  /// @pre the vertices `origin` gives a source are distinct, and a face it gives a source has
  ///      that live source face's corners (each vertex mapped by `origin.vertices`), as
  ///      PrimitiveOrigin says: the copy reads the source's cells, not its vertices.
  ViewPolyData(const SurfaceMesh& mesh, const std::vector<glm::vec3>& positions,
               const std::vector<glm::vec3>* corner_normals, const ViewPolyData& source,
               const PrimitiveOrigin& origin, ViewPolyData* spare = nullptr, CopyScratch* scratch = nullptr);

  /// How many cells `spare`'s cell arrays (offsets, connectivity, face ids) hold without
  /// growing; 0 for data left without arrays by a build that took them.
  static std::size_t room(const ViewPolyData& spare);
  /// Whether a copying build of a mesh with `slots` face slots can take `spare`'s arrays (what
  /// the constructor checks; a caller choosing among spares asks the same).
  static bool can_take(const ViewPolyData& spare, std::size_t slots);

  /// The memory of the data's arrays (every array of its poly data, colours included, and its
  /// per-point and per-corner lists; not a CopyScratch): `used` by their elements, `held` with
  /// the room past them. Each array of n elements gets room for them and a step's growth (an
  /// eighth more and a few dozen), and gives back what it holds past twice that growth, n + 2 x
  /// (n / 8 + 64) (memory a copying build took from a bigger spare, or left as the data shrank),
  /// whatever its history.
  /// The corner lists count as used once built (`updates_prepared`); `lists` is what they hold
  /// (part of `held`).
  struct Bytes {
    std::size_t used = 0, held = 0, lists = 0;
  };
  Bytes bytes() const;
  /// Where each array and list keeps its elements (that of bytes: points, point and cell data,
  /// offsets, connectivity, then the lists; null for an empty one): what tells a caller a step
  /// moved none (an update of a few elements reallocates nothing, past a growth's room).
  std::vector<const void*> blocks() const;

  /// Builds what `update` needs that the constructors left out (the corner lists,
  /// O(corners) over the pool): once, when idle after the first frame (else the next `update`
  /// does it first). Nothing to do otherwise.
  void prepare_updates();
  /// Whether this data was built by copying from a source (the constructor above, when it fits;
  /// false for a build from scratch), and whether what `update` needs is built (false only
  /// between a copying build and `prepare_updates` or the first `update`).
  bool copied() const { return copied_; }
  bool updates_prepared() const { return !corners_ || lists_; }

  vtkPolyData* poly() const { return poly_; }
  /// True when points stand for corners (the mesh has corner normals or UVs), shared by the
  /// corners of a vertex that draw alike.
  bool corner_points() const { return corners_; }

  /// Follows one step on the mesh: `mesh`, `positions` and `corner_normals` are the state after
  /// it, `change` what it changed (sizes before it, listed vertices and faces). Rewrites the
  /// listed and new elements (and the corner points of listed vertices), truncates what is gone,
  /// marks what it wrote modified. The corners of every vertex a listed or new face uses, and of
  /// every listed vertex, are grouped into points again; each point no corner uses any more is
  /// filled by the LAST point, which moves into the gap (point ids are not stable across steps).
  /// Point colours ("colors") set on the data are dropped when a point is written for other
  /// corners or the point count changes, cell colours when the cell count changes (the caller
  /// colours again). Cost: the sum over the touched vertices of valence x ways of drawing, plus
  /// the compaction (per freed point, the valence of the vertex whose last point moves).
  void update(const SurfaceMesh& mesh, const std::vector<glm::vec3>& positions,
              const std::vector<glm::vec3>* corner_normals, const PrimitiveChange& change);

  /// Moves every point to `positions` (one per vertex slot) and, when given and not empty, sets
  /// the normals from `corner_normals` (a new pose). O(points), in parallel.
  void set_positions(const std::vector<glm::vec3>& positions,
                     const std::vector<glm::vec3>* corner_normals);

 private:
  struct Writer;
  struct Candidates;
  struct Corners;
  /// The corners of vertex `v` in its list.
  Corners linked(std::uint32_t v) const;
  /// Sets the cell count (new cells' offsets and face ids) and, without corner points, the
  /// point count.
  void resize(const SurfaceMesh& mesh);
  /// Sets the point arrays' count and, with corner points, gives the per-point lists room for
  /// that many (their writers size them).
  void set_point_count(std::size_t n);
  /// Sizes the corner lists for `vertices` vertex slots and `corners` corners (new entries
  /// unlinked), with room for a step's growth, giving back too much room as `bytes` says.
  void size_lists(std::size_t vertices, std::size_t corners);
  /// How many corners of `vertices` (those below `count`) wait for a point (connectivity -1).
  std::size_t waiting_corners(const std::vector<std::uint32_t>& vertices, std::size_t count) const;
  /// The arrays for `mesh`, in one order whatever their origin: empty ones (no points, no
  /// cells), or, with `spare` (`can_take` holds), those `spare` has of each kind (points,
  /// vertex ids, texture coordinates, normals, face ids, offsets, connectivity) and its per-point
  /// vectors (not its corner lists: they go with it). Taken values stay until written (each is
  /// sized and written whole before it is read), so the cells' identity offsets and face ids are
  /// not written again; `spare` is left without data.
  void make_arrays(const SurfaceMesh& mesh, ViewPolyData* spare = nullptr);
  /// Whether `mesh` is drawn with a point per corner way of drawing (it has corner normals or UVs).
  static bool draws_corners(const SurfaceMesh& mesh);
  /// The corner lists from the drawn cells (a live cell's corners, linked to their points'
  /// vertices). A cell naming one point three times is a deleted face's, unless its face is in
  /// `collapsed_` (a live face whose three corners are one vertex drawn alike names one point
  /// three times too).
  void link_cells();
  /// Corner layout of a new mesh: groups every vertex's corners (`groups`) into points, in
  /// parallel.
  void build_corner_points(const Writer& w, const CornerGroups& groups);
  /// Whether a copying build of `mesh` from `source` as `origin` says fits (corner points on
  /// both sides, `origin` sized for `mesh`, `source` consistent).
  static bool copy_fits(const SurfaceMesh& mesh, const ViewPolyData& source, const PrimitiveOrigin& origin);
  /// Corner layout of a new mesh made out of `source`'s mesh as `origin` says (see the
  /// constructor), in `scratch`'s memory. @pre copy_fits.
  void copy_corner_points(const Writer& w, const ViewPolyData& source, const PrimitiveOrigin& origin,
                          CopyScratch& scratch);
  /// The passes of copy_corner_points, over what they know (Copying): connectivity from the
  /// source's points (in the source's numbers, each taken point noting its first corner; a
  /// corner without one waits, -1), the new numbers (one pass over the points, then one over the
  /// corners), points for the waiting corners.
  void copy_connectivity(const Writer& w, const ViewPolyData& source, const PrimitiveOrigin& origin,
                         Copying& copying);
  void renumber(const Writer& w, Copying& copying);
  void assign_waiting(const Writer& w, const std::vector<std::uint32_t>& rim_corners);
  /// A point (while building: a number among the vertex's points) that a corner of `v` other
  /// than `c` has (connectivity `conn` >= 0) and that draws like `c`, else kInvalidIndex: from
  /// `seen`, then, when `seen` is full, from every corner of `v`, so sharing is complete
  /// whatever the order of the corners.
  std::uint32_t alike_point(const Writer& w, const Candidates& seen, const Corners& corners, std::uint32_t c,
                            const vtkTypeInt64* conn) const;
  /// Gives every corner of vertex `v` that has none (connectivity -1) a point: one of the
  /// vertex's points that draws alike, else a new one (a dead point, else appended).
  /// @returns whether it wrote a point (a new one, or a dead one drawing something else now).
  bool assign_points(const Writer& w, std::uint32_t v, const Corners& corners, std::vector<std::uint32_t>& dead);
  /// Corner `c` leaves its point; a point left unused joins `dead`.
  void release(std::uint32_t c, std::vector<std::uint32_t>& dead);
  /// Removes the dead points: each takes the place of the last point.
  void compact(std::vector<std::uint32_t>& dead);
  /// Regroups the corners listed by `update` (corner layout). @returns whether a point was
  /// written (reused or appended) for other corners than before.
  bool update_corner_points(const SurfaceMesh& mesh, const std::vector<glm::vec3>& positions,
                            const std::vector<glm::vec3>* corner_normals, const PrimitiveChange& change);
  /// Links every corner `c` to `vertex_of(c)` (kInvalidIndex: none, a deleted face's), over the
  /// pool: the lists of a new state with `vertices` vertex slots.
  template <class VertexOf>
  void link_all(std::size_t corners, std::size_t vertices, const VertexOf& vertex_of);
  void link(std::uint32_t c, std::uint32_t v);
  void unlink(std::uint32_t c);
  void modified();

  bool corners_ = false;
  bool lists_ = false;        // the corner lists below are built (corner layout)
  bool copied_ = false;       // built by copying from a source
  std::size_t vertices_ = 0;  // vertex slots of the mesh drawn
  vtkSmartPointer<vtkPolyData> poly_;
  // Corner layout: the corners of each vertex slot, as a doubly linked list through the corners
  // (kInvalidIndex ends it), and the vertex each corner is linked to (kInvalidIndex: a corner
  // of a deleted face, linked to none): moving a vertex rewrites exactly its corners' points,
  // and its points are found from its corners.
  std::vector<std::uint32_t> first_, next_, prev_, corner_vertex_;
  // Per point: how many corners use it, and one of them (what it draws like; kInvalidIndex for
  // a point no corner uses). A corner's point is its connectivity entry.
  std::vector<std::uint32_t> uses_, point_corner_;
  // Until the lists are built after a copying build: its live faces whose three corners are one
  // vertex, ascending (what link_cells cannot tell from the cells).
  std::vector<std::uint32_t> collapsed_;
};

}  // namespace deepcut

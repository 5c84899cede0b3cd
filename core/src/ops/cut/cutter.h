// SPDX-License-Identifier: MIT
#pragma once
// The cut's state and stages (ops/cut/cut.cpp states them); the crossings, the new vertices
// where the plane crosses edges and the faces made around them, are in ops/cut/crossings.cpp.
// Private to the cut.

#include <cstddef>
#include <array>
#include <cstdint>
#include <utility>
#include <vector>

#include "deepcut/core/mesh_editor.h"
#include "deepcut/core/ops/cut.h"
#include "ops/common/crossing_table.h"
#include "ops/common/placement.h"
#include "ops/common/posed_overlay.h"
#include "ops/cut/caps.h"
#include "ops/cut/face_lists.h"
#include "uninit_vector.h"

namespace deepcut::detail {

/// One cut of a mesh by a plane, as cut_mesh makes it: run() goes through the stages in order.
class Cutter {
 public:
  Cutter(SurfaceMesh& mesh, const std::vector<glm::vec3>& posed, const Plane& plane,
         const CutOptions& options, Placement placement = {})
      : mesh_(mesh), editor_(mesh), posed_(posed), placement_(placement), options_(options) {
    normal_ = glm::dvec3(plane.normal);
    point_ = glm::dvec3(plane.point);
  }

  CutResult run();

 private:
  struct Split {
    VertexId lo, hi, v;
    float t = 0.0f;  // parameter from lo to hi
  };
  struct Corner {
    VertexId v;
    glm::vec3 bary;
  };

  const Split& split_edge(VertexId a, VertexId b);
  void make_crossings();
  Corner split_corner(const Triangle& t, int ka, int kb, const Split& s) const;
  void split_crossings(FaceId f);
  // A face split_face makes from crossed face `parent`, before it is made.
  struct Planned {
    Triangle t;
    FaceId parent;
    std::array<glm::vec3, 3> bary;
  };
  void split_face(FaceId f, const Split* const* crossings);
  void make_planned(const std::vector<std::uint8_t>* moved);
  void separate_sides();
  // The place in the shared vertices (separate_sides) of each vertex on the plane, or none.
  struct SharedSlots {
    const std::vector<std::uint32_t>& shared;
    std::size_t old_shared;
    const std::vector<std::uint32_t>& fresh;
    std::uint32_t slot(std::uint32_t v, std::uint32_t first_new, const std::uint8_t* old_bits) const;
  };
  bool moved_face(const Triangle& t, const SharedSlots& slots, std::uint32_t first_copy, Triangle& moved) const;
  void move_positive_rim(std::size_t touching, const std::vector<std::uint8_t>& moved_planned, const SharedSlots& slots,
                         VertexId first_copy);
  // A flag per vertex of [first, first + flags.size()); `cap_corners`: every corner of every cap
  // face is flagged.
  struct VertexFlags {
    std::uint32_t first = 0;
    std::vector<std::uint8_t> flags;
    bool cap_corners = false;
    // The flag test, holding no copy of the flags (split_pinches copies its test).
    auto test() const {
      return [first = first, n = flags.size(), bits = flags.data()](std::uint32_t v) {
        return v >= first && v - first < n && bits[v - first] != 0;
      };
    }
  };
  template <class OneFan>
  std::vector<std::pair<VertexId, VertexId>> split_pinches(CutResult* result, const OneFan& one_fan,
                                                           std::size_t candidates);
  auto single_fans() const;
  VertexFlags capped_single_fans(std::uint32_t first_cap_face, const std::vector<CapInput>& rims,
                                 bool whole_fans) const;
  void collect_pieces(CutResult& result);
  void live_rim_by_side(std::vector<FaceId> (&out)[2]) const;
  void live_side_faces(const bool (&want)[2], const std::vector<FaceId> (&rim)[2],
                       std::vector<FaceId> (&out)[2]);
  std::vector<CapInput> rim_of_pieces(const CutResult& result) const;
  // Stages of run().
  void check_arguments() const;
  void classify_vertices(const std::uint8_t* used);
  bool classify_and_scan();
  void split_crossed_faces();
  void separate_or_drop_side();
  void cap_pieces(CutResult& result, std::vector<VertexId>& rim);

  SurfaceMesh& mesh_;
  MeshEditor editor_;
  // Posed positions: the caller's for existing vertices, ours for the ones the cut adds.
  PosedOverlay<glm::vec3> posed_;
  // Bind positions of the rim vertices: their posed crossing points unposed.
  Placement placement_;
  CutOptions options_;
  glm::dvec3 normal_, point_;
  // Signed distance to the plane and snapped sign per vertex (VertexSides; the cut
  // appends its new vertices), and the side bits of the input's vertices (split_crossed_faces;
  // separate_sides then keeps its own bits above them).
  UninitVector<float> dist_;
  std::vector<std::int8_t> sign_;
  UninitVector<std::uint8_t> side_bits_;
  bool both_sides_ = false;  // some vertex lies on each side
  CrossingTable<Split> splits_;
  NeedleMerges merges_;
  // Faces that may touch the plane: untouched ones with a corner on it, and every new face.
  std::vector<FaceId> rim_candidates_;
  // The input's faces by kind, in chunks (scan_faces): the crossed and touching ones until
  // split_crossed_faces, the ones with no corner on the plane by side (positive, negative) until
  // live_side_faces joins them with the side's rim faces. No edit of the cut touches the latter
  // (but dropping a side).
  std::vector<ScannedFaces> found_;
  // Room each side's list keeps for the faces the cut and the caps add to it (a few per crossed
  // or touching face): growing a list of most of the mesh would copy it.
  std::size_t side_room_ = 0;
  std::size_t intersections_ = 0;
  // The two crossings of each crossed face with a lone corner, in face order: needle merge
  // candidates (split_crossings), looked at once the crossings are made.
  std::vector<std::pair<VertexId, VertexId>> merge_candidates_;
  // The crossings of each crossed face, two a face in face order (the second null where the
  // plane runs through a corner), as split_face uses them: found once, by split_crossings.
  std::vector<const Split*> face_crossings_;
  // The faces split_face makes, in order, and each crossed face it removes with the place of its
  // first one there: made by make_planned (or, the positive side's faces on shared rim vertices,
  // by move_positive_rim, straight onto the vertices' copies).
  std::vector<Planned> planned_;
  std::vector<std::pair<FaceId, std::uint32_t>> crossed_;
  // The crossing vertices split_edge made, [first, end), and the positive side's copies of
  // them separate_sides made, [first, end): without needle merges each of them has one fan of
  // faces per side (single_fans).
  std::uint32_t crossings_[2] = {0, 0};
  std::uint32_t crossing_copies_[2] = {0, 0};
};

}  // namespace deepcut::detail

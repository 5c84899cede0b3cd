// SPDX-License-Identifier: MIT
// The drill's wall (wall.h): the shells of the rims, each walled sheet by sheet.
#include "ops/drill/walls/wall.h"

#include <algorithm>
#include <unordered_map>
#include <unordered_set>

#include "ops/drill/walls/wall_shell.h"
#include "union_find.h"

namespace deepcut::drill {
namespace {

using Shells = std::unordered_map<std::uint32_t, std::vector<std::size_t>>;  // root vertex -> rims

// The rims of each connected shell, by the shell's root vertex in `parent` (union-find over the
// faces' corners).
Shells group_shells(const SurfaceMesh& mesh, const std::vector<Rim>& rims,
                    std::vector<std::uint32_t>& parent) {
  parent.assign(mesh.vertex_count(), 0);
  for (std::uint32_t i = 0; i < parent.size(); ++i) parent[i] = i;
  mesh.for_each_face([&](FaceId, const Triangle& t) {
    const std::uint32_t a = detail::find_root(parent, t[0].index);
    for (int k = 1; k < 3; ++k) {
      const std::uint32_t b = detail::find_root(parent, t[k].index);
      if (a != b) parent[b] = a;
    }
  });
  Shells shells;
  for (std::size_t h = 0; h < rims.size(); ++h)
    shells[detail::find_root(parent, rims[h].vertices[0].index)].push_back(h);
  return shells;
}

// Shells with a boundary other than this drill's rims (1 per root vertex): a directed edge of one
// of their faces whose reverse no face has and that is not a rim step. The reverse is looked for
// among the faces around the edge's first corner, from a flat vertex-to-face table (a counting
// sort over the drilled shells' faces): O(their faces) in flat arrays, where a hash set of every
// directed edge cost seconds on meshes of a million triangles.
std::vector<char> open_shells(const SurfaceMesh& mesh, const std::vector<Rim>& rims, const Shells& shells,
                              std::vector<std::uint32_t>& parent) {
  std::unordered_set<std::uint64_t> rim_steps;
  for (const Rim& hole : rims)
    for (std::size_t i = 0; i < hole.vertices.size(); ++i) {
      const VertexId a = hole.vertices[i], b = hole.vertices[(i + 1) % hole.vertices.size()];
      rim_steps.insert(directed_key(a, b));
      rim_steps.insert(directed_key(b, a));
    }
  const std::vector<Triangle>& faces = mesh.faces();
  const std::size_t nv = mesh.vertex_count();
  std::vector<char> drilled(nv, 0);  // by shell root
  constexpr std::uint32_t kNoShell = ~std::uint32_t{0};
  for (const auto& [root, ids] : shells) drilled[root] = 1;
  std::vector<std::uint32_t> shell_of(faces.size(), kNoShell);
  std::vector<std::uint32_t> first(nv + 1, 0);
  mesh.for_each_face([&](FaceId f, const Triangle& t) {
    const std::uint32_t root = detail::find_root(parent, t[0].index);
    if (!drilled[root]) return;
    shell_of[f.index] = root;
    for (VertexId v : t) ++first[v.index + 1];
  });
  for (std::size_t i = 0; i < nv; ++i) first[i + 1] += first[i];
  std::vector<std::uint32_t> around(first[nv]);
  {
    std::vector<std::uint32_t> next(first.begin(), first.end() - 1);
    for (std::uint32_t f = 0; f < faces.size(); ++f)
      if (shell_of[f] != kNoShell)
        for (VertexId v : faces[f]) around[next[v.index]++] = f;
  }
  auto has_reverse = [&](VertexId a, VertexId b) {  // some face has the directed edge b -> a
    for (std::uint32_t i = first[a.index]; i < first[a.index + 1]; ++i) {
      const Triangle& g = faces[around[i]];
      for (int k = 0; k < 3; ++k)
        if (g[k] == b && g[(k + 1) % 3] == a) return true;
    }
    return false;
  };
  std::vector<char> open(nv, 0);  // by shell root
  for (std::uint32_t f = 0; f < faces.size(); ++f) {
    const std::uint32_t root = shell_of[f];
    if (root == kNoShell || open[root]) continue;
    const Triangle& t = faces[f];
    for (int k = 0; k < 3 && !open[root]; ++k) {
      const VertexId a = t[k], b = t[(k + 1) % 3];
      if (!has_reverse(a, b) && !rim_steps.count(directed_key(a, b))) open[root] = 1;
    }
  }
  return open;
}

// The wall of one closed shell: the part of the cylinder's surface (side and both end disks)
// inside that shell, bounded by the shell's rims, one sheet at a time. Rims of a sheet that cannot
// be walled are marked in `walled_ok`; false when no sheet was walled.
bool wall_shell(WallContext& ctx, const std::vector<std::size_t>& hole_ids, bool open_shell,
                std::vector<char>& walled_ok) {
  WallShell shell;
  shell.tol = 2.0 * ctx.cyl.eps;
  shell.hole_ids = hole_ids;
  if (!shell_loops(shell, ctx)) return false;
  bool any = false;
  for (int k = 0; k < 2; ++k) {
    const Loops ls = shell.sheet_loops(k, shell.rim_loops.size());
    if (ls.empty()) continue;
    const bool ok = wall_sheet(shell, ctx, ls, k, open_shell);
    for (std::size_t li = 0; li < shell.rim_loops.size(); ++li)
      if (shell.sheet[li] == k && !ok) walled_ok[shell.loop_hole[li]] = false;
    any |= ok;
  }
  return any;
}

}  // namespace

// Walls close each shell separately: its rims (which never cross each other) bound the part of
// the cylinder's surface inside it. Rims of different shells (overlapping closed components, as
// a limb modelled into a body) may cross; each shell gets its own wall.
WallResult build_drill_walls(MeshEditor& editor, const CylinderFrame& cyl, const std::vector<Rim>& rims,
                             PosedOverlay& posed, const std::vector<FaceId>& surface_faces) {
  WallResult result;
  if (rims.empty()) return result;
  WallContext ctx{editor, posed, cyl, rims, surface_faces, {}, {}, 0, 0};
  const SurfaceMesh& mesh = editor.mesh();
  std::vector<std::uint32_t> parent;
  Shells shells = group_shells(mesh, rims, parent);
  const std::vector<char> open = open_shells(mesh, rims, shells, parent);
  std::vector<char> walled_ok(rims.size(), 0);
  std::vector<std::uint32_t> order;
  for (const auto& [root, ids] : shells) order.push_back(root);
  std::sort(order.begin(), order.end());
  for (std::uint32_t root : order) {
    const auto& ids = shells[root];
    bool closed = true;
    for (std::size_t h : ids) closed &= rims[h].closed;
    if (!closed) continue;  // a rim merged with an older boundary: the shell was open already
    for (std::size_t h : ids) walled_ok[h] = 1;
    if (!wall_shell(ctx, ids, open[root] != 0, walled_ok))  // builds nothing when it returns false
      for (std::size_t h : ids) walled_ok[h] = 0;
  }
  result.walled = std::move(walled_ok);
  finish_wall_attributes(ctx);
  result.wall_triangles = ctx.faces.size();
  result.triangles_removed = ctx.removed;
  return result;
}

}  // namespace deepcut::drill

// SPDX-License-Identifier: MIT
// glTF import: meshes. A primitive is decoded into the mesh the file stores (one vertex per glTF
// vertex, skin influences on the vertices, every other attribute on the corners) and welded by
// the one `weld` into one topological vertex per (position, skin).
#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstring>

#include "deepcut/core/mesh_editor.h"
#include "deepcut/core/parallel.h"
#include "deepcut/core/weld.h"
#include "io/gltf_common.h"
#include "io/gltf_reader.h"
#include "ops/common/model_surgery.h"
#include "uninit_vector.h"

namespace deepcut::gltf_detail {
namespace {

using nlohmann::json;

constexpr std::size_t kGrain = 32768;

// The primitive as the file stores it: glTF vertex v is vertex v (-0 coordinates read as +0),
// triangle t is face t, and the corner attributes come from each corner's glTF vertex. The arrays,
// the morph targets' with them, are added to empty sets, built at once (one ArrayBuild) and handed
// to the mesh whole; the per-corner ones and the faces with the room operations get
// (operation_corner_room, operation_face_room).
SurfaceMesh file_mesh(const Floats& pos, const Uints& tris, const Influences& skin,
                      const std::vector<CornerSource>& corner_sources,
                      const std::vector<MorphTarget>& morphs) {
  SurfaceMesh mesh;
  const std::size_t nv = pos.size() / 3, nf = tris.size() / 3, nc = tris.size();
  AttributeSet vattrs = std::move(mesh.vertex_attrs()), fattrs, cattrs;
  ArrayBuild build;
  const float* p = pos.data();
  const std::uint32_t* t = tris.data();
  build.add(&vattrs.get<glm::vec3>(attr::kPosition).data(), nv, 0, [p](std::size_t v) {
    return glm::vec3(p[3 * v] + 0.0f, p[3 * v + 1] + 0.0f, p[3 * v + 2] + 0.0f);  // -0 == +0
  });
  std::vector<Triangle> faces;
  build.add(&faces, nf, operation_face_room(nf), [t](std::size_t f) {  // the weld renumbers them in place
    return Triangle{VertexId(t[3 * f]), VertexId(t[3 * f + 1]), VertexId(t[3 * f + 2])};
  });
  const char* jn[2] = {attr::kJoints0, attr::kJoints1};
  const char* wn[2] = {attr::kWeights0, attr::kWeights1};
  for (std::size_t s = 0; s < skin.sets; ++s) {
    const glm::u16vec4* joints = skin.joints.data() + s * nv;
    const glm::vec4* weights = skin.weights.data() + s * nv;
    build.add(&vattrs.add<glm::u16vec4>(jn[s]).data(), nv, 0, [joints](std::size_t v) { return joints[v]; });
    build.add(&vattrs.add<glm::vec4>(wn[s]).data(), nv, 0, [weights](std::size_t v) { return weights[v]; });
  }
  const std::size_t room = operation_corner_room(nf);
  for (const auto& source : corner_sources) {
    const float* d = source.data.data();
    if (source.comps == 2) {
      build.add(&cattrs.add<glm::vec2>(source.name).data(), nc, room,
                [d, t](std::size_t c) { return glm::vec2(d[2 * t[c]], d[2 * t[c] + 1]); });
    } else if (source.comps == 3) {
      build.add(&cattrs.add<glm::vec3>(source.name).data(), nc, room, [d, t](std::size_t c) {
        return glm::vec3(d[3 * t[c]], d[3 * t[c] + 1], d[3 * t[c] + 2]);
      });
    } else {
      const auto k = static_cast<std::size_t>(source.data_comps);
      build.add(&cattrs.add<glm::vec4>(source.name, glm::vec4(1.0f)).data(), nc, room, [d, t, k](std::size_t c) {
        const float* x = &d[k * t[c]];
        return glm::vec4(x[0], x[1], x[2], k == 4 ? x[3] : 1.0f);
      });
    }
  }
  MorphArrays morph_arrays;
  morph_arrays.add(build, nv, tris, morphs);
  build.run();
  vattrs.resize(nv);  // every array has its size already: this sets the sets' sizes
  fattrs.resize(nf);
  cattrs.resize(nc);
  // read_triangles checked every index against the vertex count: assign need not check them again.
  detail::TrustedAssign::assign(mesh, std::move(faces), std::move(vattrs), std::move(fattrs), std::move(cattrs));
  morph_arrays.put_into(mesh);
  return mesh;
}

// What sanitising a primitive's skin influences repaired (InfluenceSanitiser).
struct InfluenceRepairs {
  std::size_t renormalised = 0, out_of_range = 0, zero = 0, bad_weights = 0, duplicates = 0;
  InfluenceRepairs& operator+=(const InfluenceRepairs& o) {
    renormalised += o.renormalised;
    out_of_range += o.out_of_range;
    zero += o.zero;
    bad_weights += o.bad_weights;
    duplicates += o.duplicates;
    return *this;
  }
  // What was repaired since `before` (a count this one started from).
  InfluenceRepairs since(const InfluenceRepairs& before) const {
    return {renormalised - before.renormalised, out_of_range - before.out_of_range, zero - before.zero,
            bad_weights - before.bad_weights, duplicates - before.duplicates};
  }
};

// A primitive's influences as the file gives them (up to two sets of four per vertex, as plain
// pointers) and what sanitising them needs to know of the skin.
struct InfluenceSanitiser {
  std::size_t sets = 0;
  // Set s's joints: vertex v's four at joints[s] + v * joint_stride[s], components of
  // joint_type (unsigned bytes or shorts where the file holds them, else decoded 32-bit ones).
  const unsigned char* joints[2] = {};
  std::size_t joint_stride[2] = {};
  int joint_type = kUnsignedInt;  // every set's (read_influences reads all in the file or decodes all)
  const float* weights[2] = {};
  int joint_count = -1;            // the skin's joints; < 0 without a skin (joints then unchecked)
  std::uint32_t file_joints = 0;   // joints as the file numbers them (before duplicates merged)
  const std::uint32_t* remap = nullptr;  // file joint -> merged joint, `remap_size` of them
  std::size_t remap_size = 0;

  // Vertex v's influences, sanitised into `skin` (`nv` vertices per set); its repairs counted into
  // `r`. `kSets` is `sets` (1 or 2) as a constant: the loops over the slots unroll.
  template <int kSets, int kJointType>
  void run(std::size_t v, std::size_t nv, Influences& skin, InfluenceRepairs& r) const {
    constexpr int slots = 4 * kSets;
    std::uint16_t jj[8] = {};
    float ww[8] = {};
    std::uint32_t raw[8] = {};
    // The validator's test (ACCESSOR_WEIGHTS_NON_NORMALIZED): the positive weights, summed in
    // float, lie within 2e-7 per weight of 1. (It leaves a repeated joint's weight out of the
    // sum; here it counts, since merging the repeats adds it to the first.)
    float sum = 0.0f, tolerance = 0.0f;
    const std::size_t repeats_before = r.duplicates;
    for (int k = 0; k < slots; ++k) {
      std::uint32_t joint = joint_at<kJointType>(joints[k / 4] + v * joint_stride[k / 4], k % 4);
      float weight = weights[k / 4][4 * v + std::size_t(k % 4)];
      if (!std::isfinite(weight) || weight < 0.0f) {
        ++r.bad_weights;
        weight = 0.0f;
      }
      if (joint_count >= 0 && joint >= file_joints) {
        // Dropped, and the slot points at joint 0: a vertex left with no weight is bound to its
        // first slot's joint, which must exist.
        r.out_of_range += weight > 0.0f;
        weight = 0.0f;
        joint = 0;
      }
      raw[k] = joint;
      bool repeated = false;
      for (int i = 0; i < k && weight > 0.0f; ++i) repeated = repeated || (raw[i] == joint && ww[i] > 0.0f);
      r.duplicates += repeated;
      if (weight > 0.0f) {
        sum += weight;
        tolerance += 2e-7f;
      }
      if (joint < remap_size) joint = remap[joint];
      if (joint > 65535u) joint = 0;
      jj[k] = static_cast<std::uint16_t>(joint);
      ww[k] = weight;
    }
    if (sum > 0.0f && std::abs(sum - 1.0f) > tolerance) ++r.renormalised;
    // The weights are finite and >= 0 now; two slots of positive weight name one joint only
    // after a repeat, through a remap or when a joint past 65535 became 0: else there is nothing
    // for normalize_influences to merge.
    const bool distinct =
        r.duplicates == repeats_before && remap_size == 0 && joint_count >= 0 && file_joints <= 65536u;
    if (!(distinct ? renormalize_influences(jj, ww, slots) : normalize_influences(jj, ww, slots))) ++r.zero;
    for (std::size_t s = 0; s < kSets; ++s) {
      skin.joints[s * nv + v] = glm::u16vec4(jj[4 * s], jj[4 * s + 1], jj[4 * s + 2], jj[4 * s + 3]);
      skin.weights[s * nv + v] = glm::vec4(ww[4 * s], ww[4 * s + 1], ww[4 * s + 2], ww[4 * s + 3]);
    }
  }
  // Component `c` of the joints at `p` (a vertex's four), as the decode reads it (to_uint).
  template <int kJointType>
  static std::uint32_t joint_at(const unsigned char* p, int c) {
    if constexpr (kJointType == kUnsignedByte) {
      return p[c];
    } else if constexpr (kJointType == kUnsignedShort) {
      std::uint16_t j;
      std::memcpy(&j, p + 2 * c, 2);
      return j;
    } else {
      std::uint32_t j;
      std::memcpy(&j, p + 4 * c, 4);
      return j;
    }
  }
  // Whether vertex v's influences are vertex u's, byte for byte (joints as the file stores them).
  template <int kJointType>
  bool same_as(std::size_t v, std::size_t u) const {
    constexpr std::size_t joint_bytes = kJointType == kUnsignedByte    ? 4
                                        : kJointType == kUnsignedShort ? 8
                                                                       : 16;
    for (std::size_t s = 0; s < sets; ++s)
      if (!same_bytes<joint_bytes>(joints[s] + v * joint_stride[s], joints[s] + u * joint_stride[s]) ||
          !same_bytes<16>(weights[s] + 4 * v, weights[s] + 4 * u))
        return false;
    return true;
  }
  // Whether the `kBytes` (4, 8 or 16) at `a` and `b` are the same: compared as whole words.
  template <std::size_t kBytes>
  static bool same_bytes(const void* a, const void* b) {
    if constexpr (kBytes == 4) {
      std::uint32_t x, y;
      std::memcpy(&x, a, 4);
      std::memcpy(&y, b, 4);
      return x == y;
    } else {
      std::uint64_t x[kBytes / 8], y[kBytes / 8];
      std::memcpy(x, a, kBytes);
      std::memcpy(y, b, kBytes);
      std::uint64_t diff = 0;
      for (std::size_t i = 0; i < kBytes / 8; ++i) diff |= x[i] ^ y[i];
      return diff == 0;
    }
  }
  // Vertices [b, e) sanitised (run). Sanitising is a function of a vertex's influences alone, so
  // a vertex whose influences are those of the vertex before it gets that one's result and
  // repairs: most vertices of a part bound to one joint, and a seam's copies of a vertex, do.
  template <int kJointType>
  InfluenceRepairs run_all(std::size_t b, std::size_t e, std::size_t nv, Influences& skin) const {
    InfluenceRepairs r, last;
    for (std::size_t v = b; v < e; ++v) {
      if (v > b && same_as<kJointType>(v, v - 1)) {
        for (std::size_t s = 0; s < sets; ++s) {
          skin.joints[s * nv + v] = skin.joints[s * nv + v - 1];
          skin.weights[s * nv + v] = skin.weights[s * nv + v - 1];
        }
        r += last;
        continue;
      }
      const InfluenceRepairs before = r;
      sets == 1 ? run<1, kJointType>(v, nv, skin, r) : run<2, kJointType>(v, nv, skin, r);
      last = r.since(before);
    }
    return r;
  }
  // Vertices [b, e) sanitised (run); their repairs.
  InfluenceRepairs operator()(std::size_t b, std::size_t e, std::size_t nv, Influences& skin) const {
    if (joint_type == kUnsignedByte) return run_all<kUnsignedByte>(b, e, nv, skin);
    if (joint_type == kUnsignedShort) return run_all<kUnsignedShort>(b, e, nv, skin);
    return run_all<kUnsignedInt>(b, e, nv, skin);
  }
};

// One joint set of a primitive, with its weights.
struct SkinSetData {
  Uints joints;          // decoded, unless read where the file holds them (`stored`)
  AccessorBytes stored;  // where the file holds the joints, when read there
  Floats weights;
};

// Joints that are unsigned bytes or shorts in a bufferView, not sparse, are read where the file
// holds them (checked and charged as the decode would: accessor_bytes), not decoded to 32 bits
// first; when every set's are, of one component type: that type, else 0.
int joint_type_in_file(const tinygltf::Model& gltf, const tinygltf::Primitive& p) {
  int joint_type = -1;
  for (int s = 0; s < 2; ++s) {
    auto j = p.attributes.find("JOINTS_" + std::to_string(s));
    if (j == p.attributes.end() || p.attributes.count("WEIGHTS_" + std::to_string(s)) == 0) break;
    const int ja = j->second;
    const tinygltf::Accessor* acc = ja >= 0 && static_cast<std::size_t>(ja) < gltf.accessors.size()
                                        ? &gltf.accessors[std::size_t(ja)]
                                        : nullptr;
    const bool in_file = acc && acc->bufferView >= 0 && !acc->sparse.isSparse &&
                         (acc->componentType == kUnsignedByte || acc->componentType == kUnsignedShort) &&
                         (joint_type < 0 || joint_type == acc->componentType);
    joint_type = in_file ? acc->componentType : 0;
    if (!in_file) break;
  }
  return joint_type < 0 ? 0 : joint_type;
}

// The sanitiser of `sets` (their joints of `joint_type` where the file holds them, or decoded
// when it is 0), for a skin of `joint_count` joints whose duplicates `remap` merges (may be null).
InfluenceSanitiser influence_sanitiser(const std::vector<SkinSetData>& sets, int joint_type, int joint_count,
                                       const std::vector<std::uint32_t>* remap) {
  InfluenceSanitiser sanitise;
  sanitise.sets = sets.size();
  sanitise.joint_type = joint_type != 0 ? joint_type : kUnsignedInt;
  for (std::size_t s = 0; s < sets.size(); ++s) {
    if (sanitise.joint_type == kUnsignedInt) {
      sanitise.joints[s] = reinterpret_cast<const unsigned char*>(sets[s].joints.data());
      sanitise.joint_stride[s] = 4 * sizeof(std::uint32_t);
    } else {
      sanitise.joints[s] = sets[s].stored.base;
      sanitise.joint_stride[s] = sets[s].stored.stride;
    }
    sanitise.weights[s] = sets[s].weights.data();
  }
  // Joint indices as the file numbers them, and how they are numbered once duplicate joints of
  // the skin are merged (read_skins).
  sanitise.joint_count = joint_count;
  sanitise.file_joints = remap && !remap->empty() ? static_cast<std::uint32_t>(remap->size())
                         : joint_count >= 0       ? static_cast<std::uint32_t>(joint_count)
                                                  : 0u;
  sanitise.remap = remap ? remap->data() : nullptr;
  sanitise.remap_size = remap ? remap->size() : 0;
  return sanitise;
}

}  // namespace

Primitive Reader::read_primitive(const tinygltf::Primitive& p, const std::string& where, int joint_count, std::size_t targets) {
  Primitive out;
  out.material = p.material;
  if (p.material >= 0 && static_cast<std::size_t>(p.material) >= gltf_.materials.size())
    fail(where + " uses material " + std::to_string(p.material) + ", which does not exist");
  if (p.mode != TINYGLTF_MODE_TRIANGLES && p.mode != TINYGLTF_MODE_TRIANGLE_STRIP && p.mode != TINYGLTF_MODE_TRIANGLE_FAN &&
      p.mode != -1) {
    static const char* names[] = {"POINTS", "LINES", "LINE_LOOP", "LINE_STRIP"};
    fail(where + " has mode " + (p.mode >= 0 && p.mode < 4 ? names[p.mode] : std::to_string(p.mode)) +
         "; only triangle primitives are supported");
  }
  const Floats pos = read_positions(p, where);
  const std::size_t nv = pos.size() / 3;
  out.gltf_vertices = nv;
  const Uints tris = read_triangles(p, where, nv);
  const Influences skin = read_influences(p, where, nv, joint_count);
  const std::vector<CornerSource> corner_sources = read_corner_sources(p, where, nv);
  const std::vector<MorphTarget> morphs = read_targets(p, where, nv, tris.size(), targets);

  // Weld: one topological vertex per distinct (position, skin, morph deltas); numbered by first use.
  out.mesh = file_mesh(pos, tris, skin, corner_sources, morphs);
  const WeldReport welded = weld(out.mesh, {options_.weld ? WeldKey::PositionAndSkin : WeldKey::None});
  out.welded_merged = welded.merged;
  if (welded.kept_apart)
    problem("weld-kept-apart", welded.kept_apart,
            {morphs.empty() ? "vertex shares a position with different skin weights (kept apart)"
                            : "vertex shares a position with different skin weights or morph deltas (kept apart)",
             morphs.empty() ? "vertices share a position with different skin weights (kept apart)"
                            : "vertices share a position with different skin weights or morph deltas (kept apart)"},
            where);
  if (welded.dropped)
    problem("unreferenced-vertices-dropped", welded.dropped, {"unreferenced vertex dropped", "unreferenced vertices dropped"},
            where);
  return out;
}

Floats Reader::read_positions(const tinygltf::Primitive& p, const std::string& where) {
  auto pos_it = p.attributes.find("POSITION");
  if (pos_it == p.attributes.end()) fail(where + " has no POSITION attribute");
  int comps = 0;
  auto pos = read_floats(pos_it->second, "POSITION", &comps);
  if (comps != 3) fail(where + ": POSITION is not VEC3");
  const std::size_t bad = first_bad(pos.size(), [&](std::size_t i) { return !std::isfinite(pos[i]); });
  if (bad < pos.size()) fail(where + ": POSITION " + std::to_string(bad / 3) + " is not finite (NaN or Inf)");
  return pos;
}

// Triangles as glTF vertex indices (strips and fans converted).
Uints Reader::read_triangles(const tinygltf::Primitive& p, const std::string& where, std::size_t nv) {
  Uints idx;
  if (p.indices >= 0) {
    int ic = 0;
    idx = read_uints(p.indices, "indices", &ic);
    if (ic != 1) fail(where + ": indices are not SCALAR");
    if (gltf_.accessors[p.indices].componentType == kFloat) fail(where + ": indices must be integers");
    const auto limit = static_cast<std::uint32_t>(nv);  // nv <= kMaxAccessorElements; 32 bits compare faster
    const std::size_t i = first_bad(idx.size(), [&](std::size_t k) { return idx[k] >= limit; });
    if (i < idx.size())
      fail(where + ": index " + std::to_string(idx[i]) + " (position " + std::to_string(i) + ") is past the " +
           std::to_string(nv) + " vertices");
  } else {
    detail::UninitVector<std::uint32_t> all(nv);
    for (std::size_t i = 0; i < nv; ++i) all[i] = static_cast<std::uint32_t>(i);
    idx = Uints(std::move(all));
  }
  detail::UninitVector<std::uint32_t> tris;
  if (p.mode == TINYGLTF_MODE_TRIANGLE_STRIP) {
    for (std::size_t i = 2; i < idx.size(); ++i) {
      if (i % 2 == 0) tris.insert(tris.end(), {idx[i - 2], idx[i - 1], idx[i]});
      else tris.insert(tris.end(), {idx[i - 1], idx[i - 2], idx[i]});
    }
    problem("triangle-strips-converted", 1,
            {"primitive was a triangle strip (converted to triangles)", "primitives were triangle strips (converted to triangles)"},
            where);
  } else if (p.mode == TINYGLTF_MODE_TRIANGLE_FAN) {
    for (std::size_t i = 2; i < idx.size(); ++i) tris.insert(tris.end(), {idx[0], idx[i - 1], idx[i]});
    problem("triangle-fans-converted", 1,
            {"primitive was a triangle fan (converted to triangles)", "primitives were triangle fans (converted to triangles)"},
            where);
  } else {
    if (idx.size() % 3 != 0) fail(where + ": index count " + std::to_string(idx.size()) + " is not a multiple of 3");
    return idx;
  }
  return Uints(std::move(tris));
}

// Up to two sets of four influences per vertex, sanitised (InfluenceSanitiser); every repair is noted.
Influences Reader::read_influences(const tinygltf::Primitive& p, const std::string& where, std::size_t nv,
                                   int joint_count) {
  std::vector<SkinSetData> sets;
  const int joint_type = joint_type_in_file(gltf_, p);
  for (int s = 0; s < 2; ++s) {
    auto j = p.attributes.find("JOINTS_" + std::to_string(s));
    auto w = p.attributes.find("WEIGHTS_" + std::to_string(s));
    if (j == p.attributes.end() || w == p.attributes.end()) break;
    SkinSetData d;
    int jc = 0, wc = 0;
    std::size_t joints_read = 0;
    if (joint_type != 0) {
      d.stored = accessor_bytes(j->second, "JOINTS", "JOINTS (accessor " + std::to_string(j->second) + ")",
                                sizeof(std::uint32_t), &jc);
      joints_read = d.stored.acc->count * std::size_t(jc);
    } else {
      d.joints = read_uints(j->second, "JOINTS", &jc);
      joints_read = d.joints.size();
    }
    d.weights = read_floats(w->second, "WEIGHTS", &wc);
    if (jc != 4 || wc != 4 || joints_read != 4 * nv || d.weights.size() != 4 * nv)
      fail(where + ": JOINTS_" + std::to_string(s) + "/WEIGHTS_" + std::to_string(s) + " must be VEC4 with one per vertex");
    sets.push_back(std::move(d));
  }
  const InfluenceSanitiser sanitise = influence_sanitiser(sets, joint_type, joint_count, joint_remap_);
  Influences skin;
  skin.sets = sets.size();
  skin.joints.resize(sets.size() * nv);  // every element written below
  skin.weights.resize(sets.size() * nv);
  const InfluenceRepairs repairs = parallel_reduce(
      sets.empty() ? 0 : nv, kGrain, InfluenceRepairs(),
      [&](std::size_t b, std::size_t e) { return sanitise(b, e, nv, skin); },
      [](InfluenceRepairs a, const InfluenceRepairs& b) { return a += b; });
  if (repairs.bad_weights)
    problem("weights-invalid", repairs.bad_weights,
            {"weight was negative or NaN (set to 0)", "weights were negative or NaN (set to 0)"}, where);
  if (repairs.renormalised)
    problem("weights-normalised", repairs.renormalised,
            {"vertex had weights not summing to 1 (normalised)", "vertices had weights not summing to 1 (normalised)"}, where);
  if (repairs.out_of_range)
    problem("joints-past-skin", repairs.out_of_range,
            {"influence named a joint past the skin (dropped)", "influences named a joint past the skin (dropped)"},
            where);
  if (repairs.duplicates)
    problem("influences-duplicate-joint", repairs.duplicates,
            {"influence named a joint its vertex already had (weights summed)",
             "influences named a joint their vertex already had (weights summed)"},
            where);
  if (repairs.zero)
    problem("weights-zero", repairs.zero,
            {"vertex had no weight (bound to its first joint)", "vertices had no weight (bound to their first joint)"}, where);
  return skin;
}

std::vector<CornerSource> Reader::read_corner_sources(const tinygltf::Primitive& p, const std::string& where,
                                                      std::size_t nv) {
  std::vector<CornerSource> corner_sources;
  for (const auto& [name, accessor] : p.attributes) {
    if (name == "POSITION" || name.rfind("JOINTS_", 0) == 0 || name.rfind("WEIGHTS_", 0) == 0) {
      if ((name.rfind("JOINTS_", 0) == 0 || name.rfind("WEIGHTS_", 0) == 0) && name.back() > '1')
        problem("influence-sets-dropped", 1,
                {"influence set dropped (at most 8 influences are kept)", "influence sets dropped (at most 8 influences are kept)"},
                name + " (" + where + ")");
      continue;
    }
    CornerSource cs;
    if (name == "NORMAL") { cs.name = attr::kNormal; cs.comps = 3; }
    else if (name == "TANGENT") { cs.name = attr::kTangent; cs.comps = 4; }
    else if (name == "COLOR_0") { cs.name = attr::kColor0; cs.comps = 4; }
    else if (name.rfind("TEXCOORD_", 0) == 0) {
      const std::string set = name.substr(9);
      if (set.empty() || set.size() > 2 || !std::all_of(set.begin(), set.end(), [](unsigned char c) { return std::isdigit(c); })) {
        problem("attribute-invalid-name-dropped", 1,
                {"attribute dropped (not a valid glTF attribute name)", "attributes dropped (not valid glTF attribute names)"},
                name + " (" + where + ")");
        continue;
      }
      cs.name = attr::uv_name(std::stoi(set));
      cs.comps = 2;
    }
    else {
      problem("attribute-dropped", 1, {"attribute dropped (not supported)", "attributes dropped (not supported)"},
              name + " (" + where + ")");
      continue;
    }
    cs.data = read_floats(accessor, name.c_str(), &cs.data_comps);
    if (cs.data.size() / std::size_t(std::max(cs.data_comps, 1)) != nv) fail(where + ": " + name + " count differs from POSITION count");
    const bool ok = cs.data_comps == cs.comps || (name == "COLOR_0" && cs.data_comps == 3);
    if (!ok) fail(where + ": " + name + " has " + std::to_string(cs.data_comps) + " components");
    corner_sources.push_back(std::move(cs));
  }
  return corner_sources;
}

void Reader::read_meshes() {
  // The skin a mesh is drawn with decides the valid joint range of its influences.
  std::vector<int> mesh_joints(gltf_.meshes.size(), -1), mesh_skin(gltf_.meshes.size(), -1);
  for (const auto& n : model_.nodes)
    if (n.mesh >= 0 && n.skin >= 0) {
      mesh_joints[n.mesh] = static_cast<int>(model_.skins[n.skin].joints.size());
      mesh_skin[n.mesh] = n.skin;
    }
  for (std::size_t m = 0; m < gltf_.meshes.size(); ++m) {
    const auto& g = gltf_.meshes[m];
    Mesh mesh;
    mesh.name = g.name;
    const json& r = raw_.contains("meshes") && m < raw_["meshes"].size() ? raw_["meshes"][m] : json::object();
    mesh.extras_json = dump_member(r, "extras");
    const std::string mesh_where = "mesh " + std::to_string(m) + (g.name.empty() ? "" : " '" + g.name + "'");
    const std::size_t targets = mesh_target_count(m, mesh_where);
    read_mesh_weights(mesh, m, mesh_where, targets);
    for (std::size_t p = 0; p < g.primitives.size(); ++p) {
      const std::string where = mesh_where + " primitive " + std::to_string(p);
      joint_remap_ = mesh_skin[m] >= 0 ? &skin_joint_remap_[std::size_t(mesh_skin[m])] : nullptr;
      Primitive prim = read_primitive(g.primitives[p], where, mesh_joints[m], targets);
      joint_remap_ = nullptr;
      if (r.contains("primitives") && p < r["primitives"].size()) prim.extras_json = dump_member(r["primitives"][p], "extras");
      mesh.primitives.push_back(std::move(prim));
    }
    model_.meshes.push_back(std::move(mesh));
  }
}

}  // namespace deepcut::gltf_detail

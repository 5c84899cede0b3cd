// SPDX-License-Identifier: MIT
#pragma once
// The glTF reader (private to core): tinygltf parses the container, buffers and images; the
// Reader decodes accessors with bounds checks and reads one glTF section per method. Its methods
// live in gltf_read.cpp (sandbox, container, accessors), gltf_read_scene.cpp (nodes, skins,
// animations, images, objects carried through), gltf_read_mesh.cpp (meshes and primitives) and
// gltf_read_targets.cpp (morph targets, their weights and the animation channels that drive them).

#include <cstdint>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>
#include <tiny_gltf.h>

#include "deepcut/core/errors.h"
#include "deepcut/core/io/gltf.h"

namespace deepcut::gltf_detail {

// Keeps messages to one readable line: control characters become spaces and any run of more
// than 100 characters without a space (a data URI quoted by tinygltf) is cut short.
std::string one_line(const std::string& text);

// `o[key]` as JSON text, or "" when `o` is not an object or lacks `key`.
std::string dump_member(const nlohmann::json& o, const char* key);

// A primitive's skin influences per glTF vertex: `sets` sets of four (JOINTS_n / WEIGHTS_n),
// sanitised (finite non-negative weights summing to 1, joints inside the skin).
struct Influences {
  std::size_t sets = 0;
  std::vector<glm::u16vec4> joints;  // set s of glTF vertex v at s * vertex_count + v
  std::vector<glm::vec4> weights;
};

// A per-vertex glTF attribute (NORMAL, TANGENT, COLOR_0, TEXCOORD_n) that becomes a corner
// attribute.
struct CornerSource {
  std::string name;  // the attr:: name
  int comps;         // stored components (2, 3 or 4)
  std::vector<float> data;
  int data_comps;    // components in the file (COLOR_0 may have 3)
};

// One morph target of a primitive, per glTF vertex: 3 floats each (POSITION zeros when the file
// gave none; NORMAL and TANGENT empty when it gave none or the primitive has no base attribute).
struct MorphTarget {
  std::vector<float> position, normal, tangent;
};

// Adds the targets to the primitive as the file stores it (glTF vertex v is vertex v, triangle t
// is face t): `attr::morph_position_name(i)` per vertex, the normal and tangent deltas per corner.
void add_morph_targets(SurfaceMesh& mesh, const std::vector<std::uint32_t>& tris, const std::vector<MorphTarget>& targets);

// A phrase that follows a count, in the singular and the plural.
struct MorphCounted {
  std::string one, many;
};

class Reader {
 public:
  /// Reads the file at `path`, or `*memory` (then `path` only names it and no file is read).
  Reader(std::string path, const ImportOptions& options, const std::vector<unsigned char>* memory = nullptr)
      : path_(std::move(path)), options_(options), memory_(memory) {}
  Model read();

 private:
  [[noreturn]] void fail(const std::string& what) const {
    throw Error(ErrorCode::InvalidInput, path_ + ": " + one_line(what));
  }
  void note(const std::string& what) { model_.import_notes.push_back(what); }

  // gltf_read.cpp
  void parse_container();
  void check_uris() const;
  std::vector<float> read_floats(int accessor, const char* what, int* components_out = nullptr);
  std::vector<std::uint32_t> read_uints(int accessor, const char* what, int* components_out = nullptr);
  template <class T, class Convert>
  std::vector<T> decode(int accessor, const char* what, int* components_out, Convert convert);
  const unsigned char* view_bytes(int view, std::size_t offset, std::size_t stride, std::size_t elem,
                                  std::size_t count, const std::string& what);

  // gltf_read_scene.cpp
  void read_nodes();
  void read_skins();
  void read_animations();
  void read_images();
  void read_passthrough();

  // gltf_read_mesh.cpp
  void read_meshes();
  Primitive read_primitive(const tinygltf::Primitive& p, const std::string& where, int joint_count, std::size_t targets);
  std::vector<float> read_positions(const tinygltf::Primitive& p, const std::string& where);
  std::vector<std::uint32_t> read_triangles(const tinygltf::Primitive& p, const std::string& where, std::size_t nv);
  Influences read_influences(const tinygltf::Primitive& p, const std::string& where, std::size_t nv, int joint_count);
  std::vector<CornerSource> read_corner_sources(const tinygltf::Primitive& p, const std::string& where, std::size_t nv);

  // gltf_read_targets.cpp
  std::size_t mesh_target_count(std::size_t m, const std::string& where);
  std::vector<MorphTarget> read_targets(const tinygltf::Primitive& p, const std::string& where, std::size_t nv,
                                        std::size_t corners, std::size_t count);
  void read_mesh_weights(Mesh& mesh, std::size_t m, const std::string& where, std::size_t count);
  // Notes `count` morph things repaired or dropped at `place`: "<count> <phrase>: <place>".
  void morph_note(std::size_t count, const MorphCounted& what, const std::string& place);
  bool fit_weights_sampler(AnimationSampler& s, int output_type, std::size_t animation, std::size_t channel);
  void resolve_morph_weights();
  void charge_decode(std::size_t bytes, const std::string& what);

  std::string path_;
  ImportOptions options_;
  const std::vector<unsigned char>* memory_ = nullptr;
  std::size_t decode_left_ = 0;  // bytes that accessors may still decode to (see kDecodeBaseBytes)
  tinygltf::Model gltf_;
  nlohmann::json raw_;
  Model model_;
};

}  // namespace deepcut::gltf_detail

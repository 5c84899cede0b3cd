// SPDX-License-Identifier: MIT
#pragma once
// The glTF reader (private to core): tinygltf parses the container, buffers and images; the
// Reader decodes accessors with bounds checks and reads one glTF section per method. Its methods
// live in gltf_read.cpp (sandbox, container, accessors), gltf_read_scene.cpp (nodes, skins,
// animations, images, objects carried through), gltf_read_mesh.cpp (meshes and primitives) and
// gltf_read_targets.cpp (morph targets, their weights and the animation channels that drive them).

#include <tiny_gltf.h>

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <iterator>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "deepcut/core/errors.h"
#include "deepcut/core/io/gltf.h"
#include "deepcut/core/operation_room.h"
#include "deepcut/core/parallel.h"
#include "io/gltf_common.h"
#include "io/import_problems.h"
#include "uninit_vector.h"

namespace draco {
class Mesh;
}

namespace deepcut::gltf_detail {

// A decoded accessor, read only. Elements the file stores as the decoded type already (tightly
// packed, aligned, not sparse: most floats and 32-bit indices) are read where the file holds
// them, without a copy (the reader keeps those bytes until it returns); the rest are decoded
// into an array of its own, left uninitialised (UninitVector) since the decode writes every
// element in parallel chunks. Move-only: a copy would point into the original's array.
template <class T>
class Decoded {
 public:
  Decoded() = default;
  explicit Decoded(detail::UninitVector<T> own) : own_(std::move(own)), data_(own_.data()), size_(own_.size()) {}
  Decoded(const T* in_file, std::size_t size) : data_(in_file), size_(size) {}
  Decoded(Decoded&& o) noexcept { *this = std::move(o); }
  Decoded& operator=(Decoded&& o) noexcept {
    if (this != &o) {
      own_ = std::move(o.own_);  // the array keeps its address
      data_ = std::exchange(o.data_, nullptr);
      size_ = std::exchange(o.size_, 0);
    }
    return *this;
  }
  Decoded(const Decoded&) = delete;
  Decoded& operator=(const Decoded&) = delete;

  const T* data() const { return data_; }
  std::size_t size() const { return size_; }
  bool empty() const { return size_ == 0; }
  const T& operator[](std::size_t i) const { return data_[i]; }
  const T* begin() const { return data_; }
  const T* end() const { return data_ + size_; }
  /// `n` copies of `value`, in an array of its own.
  void assign(std::size_t n, const T& value) { *this = Decoded(detail::UninitVector<T>(n, value)); }

 private:
  detail::UninitVector<T> own_;
  const T* data_ = nullptr;
  std::size_t size_ = 0;
};
using Floats = Decoded<float>;
using Uints = Decoded<std::uint32_t>;

// Where an accessor's elements lie, each claim checked against the bytes that back it
// (Reader::accessor_bytes), before anything is decoded.
struct AccessorBytes {
  const tinygltf::Accessor* acc = nullptr;
  int comps = 0;                         // components per element
  int csize = 0;                         // bytes per component
  std::size_t elem = 0;                  // bytes per element
  std::size_t stride = 0;                // bytes from one element to the next
  const unsigned char* base = nullptr;   // the first element; null without a bufferView (zeros)
  std::size_t sparse = 0;                // sparse elements (0 when not sparse)
  int isize = 0;                         // bytes per sparse index
  const unsigned char* ibase = nullptr;  // the sparse indices
  const unsigned char* vbase = nullptr;  // the sparse values
};

// The smallest i in [0, n) where bad(i) holds, or n (in parallel chunks; the answer is the same
// whatever the thread count). Each block of a chunk is tested whole, without a branch per
// element, so the test vectorises; only a block with a bad element is searched.
template <class Bad>
std::size_t first_bad(std::size_t n, Bad&& bad) {
  constexpr std::size_t kGrain = 32768, kBlock = 256;
  return parallel_reduce(
      n, kGrain, n,
      [&](std::size_t b, std::size_t e) {
        for (std::size_t s = b; s < e; s += kBlock) {
          const std::size_t t = std::min(e, s + kBlock);
          unsigned any = 0;  // an integer: an OR of bools does not vectorise
          for (std::size_t i = s; i < t; ++i) any |= unsigned(bad(i));
          if (!any) continue;
          for (std::size_t i = s; i < t; ++i)
            if (bad(i)) return i;
        }
        return n;
      },
      [](std::size_t a, std::size_t b) { return std::min(a, b); });
}

// Keeps messages to one readable line: control characters become spaces and any run of more
// than 100 characters without a space (a data URI quoted by tinygltf) is cut short.
std::string one_line(const std::string& text);

// `o[key]` as JSON text, or "" when `o` is not an object or lacks `key`.
std::string dump_member(const nlohmann::json& o, const char* key);

// gltf_decode_meshopt.cpp. What tinygltf (built without Draco) refuses in a compressed file: a
// buffer that only stands in for EXT_meshopt_compression data (a `fallback` buffer without a URI)
// has no bytes, and a KHR_draco_mesh_compression primitive's indices accessor has no bufferView.
// When `doc` has either, sets `*patched` to the document that tinygltf is given instead (each such
// buffer a 3-byte data URI, each such primitive without `indices`) and returns true. The decoders
// never read a stand-in and take the indices from the file's own JSON (Reader::raw_).
bool stand_in_for_tinygltf(const nlohmann::json& doc, bool glb, nlohmann::json* patched);
// The .glb `glb` (`size` bytes) with its JSON chunk replaced by `json_text` and its BIN chunk kept
// as it is, or with `bin_stand_in` replaced by a 4-byte one (see Reader::glb_bin_).
std::vector<unsigned char> glb_with_json(const unsigned char* glb, std::size_t size, std::string json_text,
                                         bool bin_stand_in);

// A primitive's skin influences per glTF vertex: `sets` sets of four (JOINTS_n / WEIGHTS_n),
// sanitised (finite non-negative weights summing to 1, joints inside the skin).
struct Influences {
  std::size_t sets = 0;
  detail::UninitVector<glm::u16vec4> joints;  // set s of glTF vertex v at s * vertex_count + v
  detail::UninitVector<glm::vec4> weights;
};

// A per-vertex glTF attribute (NORMAL, TANGENT, COLOR_0, TEXCOORD_n) that becomes a corner
// attribute.
struct CornerSource {
  std::string name;  // the attr:: name
  int comps;         // stored components (2, 3 or 4)
  Floats data;
  int data_comps;    // components in the file (COLOR_0 may have 3)
};

// One morph target of a primitive, per glTF vertex: 3 floats each (POSITION zeros when the file
// gave none; NORMAL and TANGENT empty when it gave none or the primitive has no base attribute).
struct MorphTarget {
  Floats position, normal, tangent;
};

// The values fill(0), fill(1), ... as an iterator range, so that a std::vector appends them
// (insert at the end) writing each element once: growing it with resize would value-initialise
// every element first, a second pass over memory the fill then overwrites. Random access, so
// that insert measures the range with one subtraction and allocates once; like
// std::vector<bool>'s iterator its reference is a value (`fill(i)`), not a T&.
template <class T, class Fill>
class Generated {
 public:
  using iterator_category = std::random_access_iterator_tag;
  using value_type = T;
  using difference_type = std::ptrdiff_t;
  using pointer = void;
  using reference = T;
  Generated() = default;
  Generated(const Fill* fill, std::size_t i) : fill_(fill), i_(difference_type(i)) {}
  T operator*() const { return (*fill_)(std::size_t(i_)); }
  T operator[](difference_type n) const { return (*fill_)(std::size_t(i_ + n)); }
  Generated& operator++() { return *this += 1; }
  Generated operator++(int) {
    Generated old = *this;
    ++*this;
    return old;
  }
  Generated& operator--() { return *this -= 1; }
  Generated operator--(int) {
    Generated old = *this;
    --*this;
    return old;
  }
  Generated& operator+=(difference_type n) {
    i_ += n;
    return *this;
  }
  Generated& operator-=(difference_type n) { return *this += -n; }
  friend Generated operator+(Generated it, difference_type n) { return it += n; }
  friend Generated operator+(difference_type n, Generated it) { return it += n; }
  friend Generated operator-(Generated it, difference_type n) { return it -= n; }
  friend difference_type operator-(const Generated& a, const Generated& b) { return a.i_ - b.i_; }
  friend bool operator==(const Generated& a, const Generated& b) { return a.i_ == b.i_; }
  friend bool operator!=(const Generated& a, const Generated& b) { return a.i_ != b.i_; }
  friend bool operator<(const Generated& a, const Generated& b) { return a.i_ < b.i_; }
  friend bool operator>(const Generated& a, const Generated& b) { return a.i_ > b.i_; }
  friend bool operator<=(const Generated& a, const Generated& b) { return a.i_ <= b.i_; }
  friend bool operator>=(const Generated& a, const Generated& b) { return a.i_ >= b.i_; }

 private:
  const Fill* fill_ = nullptr;
  difference_type i_ = 0;
};

// Arrays of one primitive built apart and all at once: the room of each reserved on the calling
// thread, the pages of all faulted in over the whole pool (prefault), then each array's elements
// appended from `fill` in one pass (Generated), one array per thread. Reserved on the calling
// thread, the arrays come from its heap, which keeps freed memory for the next read
// (keep_freed_memory); made on a worker, an array over 64 MiB would be mapped and unmapped alone
// and its pages taken fresh every time. The one way the reader builds a mesh's and its morph
// targets' arrays (file_mesh, MorphArrays).
class ArrayBuild {
 public:
  // Grows the empty `*a` to `n` elements (capacity at least `capacity`), a[i] = fill(i) for each.
  // `a` and what `fill` reads must live until `run` returns.
  template <class T, class Fill>
  void add(std::vector<T>* a, std::size_t n, std::size_t capacity, Fill fill) {
    a->reserve(std::max(n, capacity));
    tasks_.push_back({a->data(), n * sizeof(T), [a, n, fill] {
                        a->insert(a->end(), Generated<T, Fill>(&fill, 0), Generated<T, Fill>(&fill, n));
                      }});
  }
  // The largest arrays start first, so the threads finish close together.
  void run() {
    for (const Task& t : tasks_) detail::prefault(t.data, t.bytes);
    std::stable_sort(tasks_.begin(), tasks_.end(), [](const Task& a, const Task& b) { return a.bytes > b.bytes; });
    std::vector<std::function<void()>> tasks;
    for (Task& t : tasks_) tasks.push_back(std::move(t.build));
    parallel_invoke(tasks);
  }

 private:
  struct Task {
    void* data;
    std::size_t bytes;
    std::function<void()> build;
  };
  std::vector<Task> tasks_;
};

// The morph targets' arrays of a primitive as the file stores it (glTF vertex v is vertex v,
// triangle t is face t): `attr::morph_position_name(i)` per vertex, the normal and tangent deltas
// per corner. Added to the primitive's ArrayBuild (file_mesh), put into the mesh once it is built.
class MorphArrays {
 public:
  void add(ArrayBuild& build, std::size_t nv, const Uints& tris, const std::vector<MorphTarget>& targets);
  void put_into(SurfaceMesh& mesh);

 private:
  struct Built {
    bool per_corner;
    std::string name;
    std::unique_ptr<AttributeArray<glm::vec3>> array;
  };
  std::vector<Built> built_;
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
  // Records `count` things of `kind` repaired or dropped at `place` (see io_detail::add_problem).
  void problem(const std::string& kind, std::size_t count, const io_detail::Counted& what, const std::string& place = "") {
    io_detail::add_problem(model_.import_problems, kind, count, what, place);
  }

  // gltf_read.cpp
  void parse_container();
  std::string glb_json_chunk(const unsigned char* bytes, std::size_t size) const;
  void load_tinygltf(const unsigned char* bytes, std::size_t size, bool glb, std::string json_text);
  void run_tinygltf(bool glb, ByteSpan glb_file, const std::string& json_text);
  void parse_json(const std::string& json_text);
  void check_tinygltf_errors(bool ok, const std::string& err, const std::string& fs_error) const;
  void check_uris() const;
  Floats read_floats(int accessor, const char* what, int* components_out = nullptr);
  Uints read_uints(int accessor, const char* what, int* components_out = nullptr);
  template <class T, class Convert>
  Decoded<T> decode(int accessor, const char* what, int* components_out, Convert convert);
  // Accessor `index` checked and located; its decoded size (`value_size` bytes per component) is
  // charged to decode_left_. `what` names it in messages (`what_c` when it does not exist).
  AccessorBytes accessor_bytes(int index, const char* what_c, const std::string& what, std::size_t value_size,
                               int* components_out);
  // The element each sparse value of `in` replaces (checked to lie inside the accessor).
  std::vector<std::size_t> sparse_targets(const AccessorBytes& in, const std::string& what) const;
  const unsigned char* view_bytes(int view, std::size_t offset, std::size_t stride, std::size_t elem,
                                  std::size_t count, const std::string& what);
  // Buffer `b`'s bytes: in the .glb's BIN chunk (glb_bin_) or as tinygltf loaded them.
  ByteSpan buffer_bytes(std::size_t b) const;

  // gltf_decode_meshopt.cpp, gltf_decode_draco.cpp: compressed data decoded, before anything is
  // read, into plain buffer views (and, for Draco, new accessors), so the rest of the reader sees
  // an uncompressed file. Every decoded byte is charged to decode_left_.
  void decode_meshopt_views();
  void decode_draco_primitives();
  void decode_draco_primitive(const nlohmann::json& raw_prim, tinygltf::Primitive& prim, const std::string& where);
  ByteSpan draco_bytes(const nlohmann::json& ext, const tinygltf::Primitive& prim, const std::string& where);
  std::unique_ptr<draco::Mesh> decode_draco_mesh(ByteSpan bytes, const std::string& where);
  void decode_draco_indices(const nlohmann::json& raw_prim, tinygltf::Primitive& prim,
                            const draco::Mesh& mesh, const std::string& where);
  int decode_draco_attribute(const draco::Mesh& mesh, const nlohmann::json& id, int accessor, const std::string& what);
  int add_decoded_accessor(tinygltf::Accessor acc, std::vector<unsigned char> bytes);  // over a new view
  void spend_decode_budget(std::size_t bytes, const std::string& what);
  int add_decoded_buffer(std::vector<unsigned char> bytes);  // a new buffer's index

  // gltf_read_scene.cpp
  void read_nodes();
  Node read_node(std::size_t i);
  void check_hierarchy() const;
  void read_scenes();
  void read_skins();
  void read_animations();
  Animation read_animation(std::size_t a);
  std::optional<AnimationSampler> read_sampler(const tinygltf::AnimationSampler& gs, AnimationPath path,
                                               std::size_t a, std::size_t c);
  void check_transform_sampler(AnimationSampler& s, const std::string& path, std::size_t a, std::size_t c);
  void read_images();
  void read_passthrough();
  void repair_skin(std::size_t index, Skin& skin);
  void merge_duplicate_joints(std::size_t index, Skin& skin);
  void note_dropped_extensions();

  // gltf_read_mesh.cpp
  void read_meshes();
  Primitive read_primitive(const tinygltf::Primitive& p, const std::string& where, int joint_count, std::size_t targets);
  Floats read_positions(const tinygltf::Primitive& p, const std::string& where);
  Uints read_triangles(const tinygltf::Primitive& p, const std::string& where, std::size_t nv);
  Influences read_influences(const tinygltf::Primitive& p, const std::string& where, std::size_t nv, int joint_count);
  std::vector<CornerSource> read_corner_sources(const tinygltf::Primitive& p, const std::string& where, std::size_t nv);

  // gltf_read_targets.cpp
  std::size_t mesh_target_count(std::size_t m, const std::string& where);
  std::vector<MorphTarget> read_targets(const tinygltf::Primitive& p, const std::string& where, std::size_t nv,
                                        std::size_t corners, std::size_t count);
  void read_mesh_weights(Mesh& mesh, std::size_t m, const std::string& where, std::size_t count);
  bool fit_weights_sampler(AnimationSampler& s, int output_type, std::size_t animation, std::size_t channel);
  void resolve_morph_weights();
  void charge_decode(std::size_t bytes, const std::string& what);

  std::string path_;
  ImportOptions options_;
  const std::vector<unsigned char>* memory_ = nullptr;
  FileBytes file_;  // the model file's bytes (empty when read from memory)
  // Per buffer: its bytes in the .glb's BIN chunk (in file_ or *memory_), for the buffers that
  // tinygltf was given a 1-byte stand-in for, so it did not copy the chunk; {nullptr, 0} elsewhere.
  std::vector<ByteSpan> glb_bin_;
  std::size_t decode_left_ = 0;  // bytes that accessors may still decode to (see kDecodeBaseBytes)
  // Per skin: the joint each file joint index becomes once duplicate joints are merged (empty
  // when the skin had none); `joint_remap_` points at the one of the mesh being read.
  std::vector<std::vector<std::uint32_t>> skin_joint_remap_;
  const std::vector<std::uint32_t>* joint_remap_ = nullptr;
  tinygltf::Model gltf_;
  nlohmann::json raw_;
  Model model_;
};

}  // namespace deepcut::gltf_detail

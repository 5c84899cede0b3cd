// SPDX-License-Identifier: MIT
#pragma once
/// @file attributes.h
/// Named, typed attribute arrays that grow, shrink and interpolate together (pmp's property
/// containers, VTK's InterpolateAllocate). A `SurfaceMesh` owns one `AttributeSet` per element
/// kind, so adding or splitting a vertex updates every attribute, including ones a plugin added.

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <glm/glm.hpp>
#include <glm/gtc/type_precision.hpp>
#include <map>
#include <memory>
#include <string>
#include <type_traits>
#include <typeindex>
#include <utility>
#include <vector>

#include "deepcut/core/errors.h"
#include "deepcut/core/parallel.h"
#include "deepcut/core/process_memory.h"

// Float attributes blend in vector registers where the compiler has GCC >= 12 / Clang vector
// extensions (AttributeArray::kLanes); elsewhere by the same rule one float at a time.
#if defined(__clang__) || (defined(__GNUC__) && __GNUC__ >= 12)
#define DEEPCUT_ATTRIBUTE_LANES 1
#else
#define DEEPCUT_ATTRIBUTE_LANES 0
#endif

namespace deepcut {

/// Standard attribute names. The prefix says where the data lives: `v:` one per vertex,
/// `c:` one per face corner (index 3 * face + k, so seams need no duplicated vertices),
/// `f:` one per face.
namespace attr {
inline constexpr const char* kPosition = "v:position";  ///< glm::vec3, bind space
inline constexpr const char* kJoints0 = "v:joints0";    ///< glm::u16vec4, glTF JOINTS_0
inline constexpr const char* kWeights0 = "v:weights0";  ///< glm::vec4, glTF WEIGHTS_0
inline constexpr const char* kJoints1 = "v:joints1";    ///< glm::u16vec4, glTF JOINTS_1
inline constexpr const char* kWeights1 = "v:weights1";  ///< glm::vec4, glTF WEIGHTS_1
inline constexpr const char* kNormal = "c:normal";      ///< glm::vec3 per corner, glTF NORMAL
inline constexpr const char* kTangent = "c:tangent";    ///< glm::vec4 per corner, glTF TANGENT
inline constexpr const char* kColor0 = "c:color0";      ///< glm::vec4 per corner, glTF COLOR_0
/// glm::vec2 per corner, glTF TEXCOORD_n; `uv_name(0)` is "c:uv0".
std::string uv_name(int set);
inline constexpr const char* kUv0 = "c:uv0";
/// Morph target `target` (glTF `targets[target]`): the POSITION delta of every vertex,
/// glm::vec3, "v:morph<target>:position". A primitive with targets has this array for every
/// target (zeros where the file gave no POSITION), so `MeshEditor` gives each new vertex deltas by
/// the same blend as its position.
std::string morph_position_name(int target);
/// NORMAL delta of target `target` per corner, glm::vec3, "c:morph<target>:normal" (only when
/// the file had one).
std::string morph_normal_name(int target);
/// TANGENT delta (xyz) of target `target` per corner, glm::vec3, "c:morph<target>:tangent" (only
/// when the file had one).
std::string morph_tangent_name(int target);
/// std::uint8_t per face: 1 for surface an operation created (cut caps, drill walls), which
/// gets its own material slot ("cut surface") on export.
inline constexpr const char* kCutSurface = "f:cut_surface";
}  // namespace attr

/// Type-erased base: what `SurfaceMesh` and `MeshEditor` need without knowing `T`.
///
/// The batch methods (`room_for`, `push_blend3_batch`, `push_blend_batch`, `push_copy_batch`)
/// may run at the same time on different arrays of one `AttributeSet` (a large batch runs each
/// array as a pool task of its own): an array's batch touches only that array.
class AttributeArrayBase {
 public:
  virtual ~AttributeArrayBase() = default;
  virtual std::size_t size() const = 0;
  virtual void resize(std::size_t n) = 0;
  /// Appends `count` default values (cheaper than resize for one element at a time).
  virtual void push_default(std::size_t count) = 0;
  /// Reserves room for `n` elements, so growing up to `n` never reallocates.
  virtual void reserve(std::size_t n) = 0;
  /// Appends one element: the weighted blend of `count` existing elements (`src[i]`, `w[i]`).
  /// Floating-point types blend linearly; integer types take the source of largest weight.
  virtual void push_blend(const std::uint32_t* src, const float* w, int count) = 0;
  /// Sets element `dst` to the blend of `count` elements (same rule as `push_blend`).
  virtual void set_blend(std::size_t dst, const std::uint32_t* src, const float* w, int count) = 0;
  /// Sets elements `dst .. dst + 2` (a new face's corners) to blends of elements
  /// `src .. src + 2` (its parent's corners): element `dst + k` gets weights `w[3k .. 3k + 2]`.
  /// The same values as three `set_blend` calls, in one call (the editor's per-face path).
  /// @pre the two ranges do not overlap.
  virtual void set_blend3(std::size_t dst, std::size_t src, const float* w) = 0;
  /// Appends three elements: what `push_default(3)` then `set_blend3(old size, src, w)` leaves,
  /// writing each element once (the editor's path for a face made from a parent face).
  virtual void push_blend3(std::size_t src, const float* w) = 0;
  /// Appends a copy of element `src`: what `push_default(1)` then `copy(old size, src)` leaves.
  virtual void push_copy(std::size_t src) = 0;
  /// Room for `count` more elements, grown as a std::vector grows itself (to at least double
  /// the size): the growth each batch below makes first, made ahead of it by a set whose arrays
  /// run a batch side by side (the memory then comes from the calling thread).
  virtual void room_for(std::size_t count) = 0;
  /// Batches of the appends above, one call per array for many new elements (an edit's new
  /// faces or vertices: no per-element dispatch). Each leaves exactly what the single calls,
  /// made for i = 0 .. count - 1 in turn, would:
  /// `push_blend3(3 * triples[i], w + 9 * i)` (three elements per i: a new face's corners from
  /// its parent's, where `triples` are the parents);
  virtual void push_blend3_batch(const std::uint32_t* triples, const float* w, std::size_t count) = 0;
  /// `push_blend(src + sources * i, w + sources * i, sources)` (1 <= sources <= 3);
  virtual void push_blend_batch(const std::uint32_t* src, const float* w, int sources, std::size_t count) = 0;
  /// `push_copy(src[i])`.
  virtual void push_copy_batch(const std::uint32_t* src, std::size_t count) = 0;
  /// Copies element `src` over element `dst`.
  virtual void copy(std::size_t dst, std::size_t src) = 0;
  /// Keeps only the elements listed, in that order (`keep[i]` becomes element `i`).
  virtual void gather(const std::vector<std::uint32_t>& keep) = 0;
  /// `gather(keep)` for a `keep` that increases, made in place: no allocation, the capacity stays
  /// (a cut's largest piece keeps its mesh's arrays).
  virtual void gather_in_place(const std::vector<std::uint32_t>& keep) = 0;
  /// A copy with the same capacity (room reserved for growth is kept).
  virtual std::unique_ptr<AttributeArrayBase> clone() const = 0;
  /// A copy holding only the elements listed, in that order (`keep[i]` becomes element `i`):
  /// `clone()` then `gather(keep)` without copying the whole array first.
  virtual std::unique_ptr<AttributeArrayBase> clone_subset(const std::vector<std::uint32_t>& keep) const = 0;
  /// Appends to `to`, an array of the same type, the groups of `group` consecutive elements that
  /// `keep` lists (group `k` is elements `group * k .. group * k + group - 1`), each element
  /// written once: room for exactly them is reserved, handed to `on_reserved` (nullptr: nothing;
  /// the weld faults its pages in over the pool there), then appended to run by run (consecutive groups
  /// in one copy), with no value-initialisation pass. `to` is empty (its reserved room is what
  /// `on_reserved` gets). The kernel of `clone_subset` and of a mesh's pieces copied out.
  /// @throws Error{InvalidArgument} for another type.
  virtual void gather_groups(AttributeArrayBase& to, const std::vector<std::uint32_t>& keep, std::size_t group,
                             void (*on_reserved)(void* data, std::size_t bytes)) const = 0;
  /// Takes the memory of `spare`, an array of the same type, as this empty array's room: its
  /// elements are dropped, its capacity kept (a piece copied out reuses what a dropped undo step
  /// held instead of new memory). `spare` is left empty, without memory.
  /// @throws Error{InvalidArgument} for another type.
  virtual void take_room(AttributeArrayBase& spare) = 0;
  /// Appends elements `begin .. end - 1` of `other`, an array of the same type.
  /// @throws Error{InvalidArgument} for another type.
  virtual void append_from(const AttributeArrayBase& other, std::size_t begin, std::size_t end) = 0;
  /// Swaps element `i` with element `j` of `other`, an array of the same type (undo records).
  /// @throws Error{InvalidArgument} for another type.
  virtual void swap_element(std::size_t i, AttributeArrayBase& other, std::size_t j) = 0;
  /// Bytes held, room reserved included.
  virtual std::size_t capacity_bytes() const = 0;
  virtual std::type_index type() const = 0;
  /// Bytes of one element and a pointer to element `i` (for hashing and exact comparison).
  virtual std::size_t element_bytes() const = 0;
  virtual const void* element_data(std::size_t i) const = 0;
  /// Hands the whole pages of the room past the first `keep` elements (the size at least) back
  /// to the system (release_room, process_memory.h): the capacity stays, growing into that room
  /// faults its pages in again. Allocates nothing. Returns the bytes released.
  virtual std::size_t release_room(std::size_t keep) noexcept = 0;
};

template <class T>
class AttributeArray final : public AttributeArrayBase {
  // A mesh's surgery moves elements as bytes (model_surgery_in_place: compaction in place and
  // its undo), and hashing and exact comparison read them as bytes (element_data).
  static_assert(std::is_trivially_copyable_v<T>, "attribute elements are moved as bytes");

 public:
  explicit AttributeArray(T default_value = T()) : default_(default_value) {}

  std::size_t size() const override { return data_.size(); }
  void resize(std::size_t n) override { data_.resize(n, default_); }
  void push_default(std::size_t count) override { data_.insert(data_.end(), count, default_); }
  void reserve(std::size_t n) override { data_.reserve(n); }
  void room_for(std::size_t count) override {
    const std::size_t need = data_.size() + count;
    if (need > data_.capacity()) data_.reserve(std::max(need, 2 * data_.size()));
  }
  void push_blend(const std::uint32_t* src, const float* w, int count) override {
    data_.push_back(blend(src, w, count));
  }
  void set_blend(std::size_t dst, const std::uint32_t* src, const float* w, int count) override {
    data_[dst] = blend(src, w, count);
  }
  void set_blend3(std::size_t dst, std::size_t src, const float* w) override {
    for (int k = 0; k < 3; ++k) data_[dst + k] = blend3(&data_[src], w + 3 * k);
  }
  void push_blend3(std::size_t src, const float* w) override {
    // Blended before appending: growing the vector may move the sources.
    const T* s = &data_[src];
    const T out[3] = {blend3(s, w), blend3(s, w + 3), blend3(s, w + 6)};
    data_.insert(data_.end(), out, out + 3);
  }
  void push_copy(std::size_t src) override {
    const T value = data_[src];
    data_.push_back(value);
  }
  // The batches grow the array once and append each element as it is made (no default fill
  // first; the sources do not move meanwhile). A face's corners are blended a run at a time on
  // the stack and appended in one copy; a face whose parent is still in the run appends it first.
  void push_blend3_batch(const std::uint32_t* triples, const float* w, std::size_t count) override {
    room_for(3 * count);
    T out[3 * kRun + kSpill];
    std::size_t n = 0;  // faces in `out`
    for (std::size_t i = 0; i < count; ++i) {
      const std::size_t s = 3 * std::size_t(triples[i]);
      if (n == kRun || (n > 0 && s + 3 > data_.size())) {
        data_.insert(data_.end(), out, out + 3 * n);
        n = 0;
      }
      blend_face(data_.data() + s, w + 9 * i, out + 3 * n++);
    }
    data_.insert(data_.end(), out, out + 3 * n);
  }
  void push_blend_batch(const std::uint32_t* src, const float* w, int sources, std::size_t count) override {
    room_for(count);  // a source may be an element made earlier in the batch
    for (std::size_t i = 0; i < count; ++i, src += sources, w += sources) data_.push_back(blend(src, w, sources));
  }
  void push_copy_batch(const std::uint32_t* src, std::size_t count) override {
    room_for(count);
    for (std::size_t i = 0; i < count; ++i) data_.push_back(data_[src[i]]);  // the room is there: no move
  }
  void copy(std::size_t dst, std::size_t src) override { data_[dst] = data_[src]; }
  void gather(const std::vector<std::uint32_t>& keep) override {
    std::vector<T> out(keep.size());
    parallel_for(keep.size(), 32768, [&](std::size_t b, std::size_t e) {
      for (std::size_t i = b; i < e; ++i) out[i] = data_[keep[i]];
    });
    data_.swap(out);
  }
  void gather_in_place(const std::vector<std::uint32_t>& keep) override {
    for (std::size_t i = 0; i < keep.size(); ++i) data_[i] = data_[keep[i]];  // keep[i] >= i
    data_.resize(keep.size());
  }
  std::unique_ptr<AttributeArrayBase> clone() const override {
    // Keeps the room to grow (SurfaceMesh::reserve), so a copy of a session's model edits
    // without reallocating the whole array first.
    auto out = std::make_unique<AttributeArray<T>>(default_);
    out->data_.reserve(data_.capacity());
    out->data_.assign(data_.begin(), data_.end());
    return out;
  }
  std::unique_ptr<AttributeArrayBase> clone_subset(const std::vector<std::uint32_t>& keep) const override {
    auto out = std::make_unique<AttributeArray<T>>(default_);
    gather_groups(*out, keep, 1, nullptr);
    return out;
  }
  void gather_groups(AttributeArrayBase& to, const std::vector<std::uint32_t>& keep, std::size_t group,
                     void (*on_reserved)(void* data, std::size_t bytes)) const override {
    std::vector<T>& out = same_type(to).data_;
    out.reserve(out.size() + keep.size() * group);
    if (on_reserved) on_reserved(out.data() + out.size(), keep.size() * group * sizeof(T));
    const T* src = data_.data();
    for (std::size_t i = 0; i < keep.size();) {
      std::size_t j = i + 1;
      while (j < keep.size() && keep[j] == keep[j - 1] + 1) ++j;
      if (j - i == 1 && group == 1) out.push_back(src[keep[i]]);  // a lone element: no range copy
      else out.insert(out.end(), src + std::size_t{keep[i]} * group, src + (std::size_t{keep[j - 1]} + 1) * group);
      i = j;
    }
  }
  void take_room(AttributeArrayBase& spare) override {
    std::vector<T> room = std::move(same_type(spare).data_);
    room.clear();
    data_.swap(room);
  }
  void append_from(const AttributeArrayBase& other, std::size_t begin, std::size_t end) override {
    const auto& src = same_type(other).data_;
    data_.insert(data_.end(), src.begin() + static_cast<std::ptrdiff_t>(begin),
                 src.begin() + static_cast<std::ptrdiff_t>(end));
  }
  void swap_element(std::size_t i, AttributeArrayBase& other, std::size_t j) override {
    std::swap(data_[i], same_type(other).data_[j]);
  }
  std::size_t capacity_bytes() const override { return data_.capacity() * sizeof(T); }
  std::type_index type() const override { return typeid(T); }
  std::size_t element_bytes() const override { return sizeof(T); }
  const void* element_data(std::size_t i) const override { return &data_[i]; }
  std::size_t release_room(std::size_t keep) noexcept override { return deepcut::release_room(data_, keep); }

  T& operator[](std::size_t i) { return data_[i]; }
  const T& operator[](std::size_t i) const { return data_[i]; }
  std::vector<T>& data() { return data_; }
  const std::vector<T>& data() const { return data_; }
  const T& default_value() const { return default_; }

 private:
  template <class U, class = void>
  struct GlmScalar {
    using type = U;
  };
  template <class U>
  struct GlmScalar<U, std::void_t<typename U::value_type>> {
    using type = typename U::value_type;
  };

  static const AttributeArray& same_type(const AttributeArrayBase& other) {
    if (other.type() != typeid(T)) throw Error(ErrorCode::InvalidArgument, "attribute arrays of different types");
    return static_cast<const AttributeArray&>(other);
  }
  static AttributeArray& same_type(AttributeArrayBase& other) {
    return const_cast<AttributeArray&>(same_type(static_cast<const AttributeArrayBase&>(other)));
  }
  static constexpr bool kBlends = std::is_floating_point_v<T> || std::is_floating_point_v<typename GlmScalar<T>::type>;
#if DEEPCUT_ATTRIBUTE_LANES
  // float to glm::vec4: up to four floats, blended lane by lane in one vector register (GCC >= 12
  // / Clang vector extensions), each lane by exactly the scalar rule's operations in its order.
  static constexpr bool kLanes =
      std::is_same_v<typename GlmScalar<T>::type, float> && sizeof(T) <= 16 && sizeof(T) % sizeof(float) == 0;
  using Lanes = float __attribute__((vector_size(16)));
  static Lanes splat(float x) { return Lanes{x, x, x, x}; }
  static Lanes lanes(const T& x) {
    Lanes v = splat(0.0f);
    std::memcpy(&v, &x, sizeof(T));
    return v;
  }
  static const Lanes& lanes(const Lanes& v) { return v; }
  // s[0], s[1], s[2] as lanes (the lanes past an element hold whatever follows it): three 16-byte
  // reads inside the three elements' floats where they span 16 bytes or more.
  static void lanes3(const T* s, Lanes* a) {
    constexpr int n = static_cast<int>(sizeof(T) / sizeof(float)), last = 3 * n - 4;
    if constexpr (last >= 0) {
      constexpr int o1 = n < last ? n : last, o2 = 2 * n < last ? 2 * n : last;
      constexpr int k1 = n - o1, k2 = 2 * n - o2;  // where each element starts in its read
      const auto* f = reinterpret_cast<const unsigned char*>(s);
      Lanes p1, p2;
      std::memcpy(&a[0], f, sizeof(Lanes));
      std::memcpy(&p1, f + sizeof(float) * o1, sizeof(Lanes));
      std::memcpy(&p2, f + sizeof(float) * o2, sizeof(Lanes));
      a[1] = __builtin_shufflevector(p1, p1, k1, k1 + 1, k1 + 2, k1 + 3);
      a[2] = __builtin_shufflevector(p2, p2, k2, k2 + 1, k2 + 2, k2 + 3);
    } else {
      for (int i = 0; i < 3; ++i) a[i] = lanes(s[i]);
    }
  }
  template <class At>
  static Lanes mix_lanes(At at, const float* w, int count) {
    Lanes out = splat(0.0f);
    for (int i = 0; i < count; ++i) out = out + lanes(at(i)) * splat(w[i]);
    return out;
  }
#else
  static constexpr bool kLanes = false;
#endif
  // Faces push_blend3_batch blends on the stack before appending them; a lanes store may write
  // up to 16 bytes at the last corner, `kSpill` elements past it.
  static constexpr std::size_t kRun = 32;
  static constexpr std::size_t kSpill = kLanes ? 16 / sizeof(T) : 0;
  // The one blend rule, over the `count` elements `at(0) .. at(count - 1)`: floating types mix
  // by the weights, ((0 + a0 w0) + a1 w1) + a2 w2 in each component; others take the element
  // of the largest weight.
  template <class At>
  static T mix(At at, const float* w, int count) {
#if DEEPCUT_ATTRIBUTE_LANES
    if constexpr (kLanes) {
      const Lanes v = mix_lanes(at, w, count);
      T out;
      std::memcpy(&out, &v, sizeof(T));
      return out;
    }
#endif
    if constexpr (kBlends) {
      T out = T(0);
      for (int i = 0; i < count; ++i) out += at(i) * w[i];
      return out;
    } else {
      int best = 0;
      for (int i = 1; i < count; ++i)
        if (w[i] > w[best]) best = i;
      return at(best);
    }
  }
  T blend(const std::uint32_t* src, const float* w, int count) const {
    return mix([&](int i) -> const T& { return data_[src[i]]; }, w, count);
  }
  // `blend` of the three consecutive elements at `s`.
  static T blend3(const T* s, const float* w) {
    return mix([s](int i) -> const T& { return s[i]; }, w, 3);
  }
  // out[k] = blend3(s, w + 3 k) for the three corners of a face, `out` apart from `s` with room
  // for kSpill more elements: with lanes, the sources are read once for the three.
  static void blend_face(const T* s, const float* w, T* out) {
#if DEEPCUT_ATTRIBUTE_LANES
    if constexpr (kLanes) {
      Lanes a[3];
      lanes3(s, a);
      for (int k = 0; k < 3; ++k) {
        const Lanes v = mix_lanes([&a](int i) -> const Lanes& { return a[i]; }, w + 3 * k, 3);
        std::memcpy(static_cast<void*>(out + k), &v, sizeof(Lanes));  // past it: written next, or spill room
      }
      return;
    }
#endif
    for (int k = 0; k < 3; ++k) out[k] = blend3(s, w + 3 * k);
  }

  std::vector<T> data_;
  T default_;
};

/// The attributes of one element kind, all of the same size, kept sorted by name.
class AttributeSet {
 public:
  AttributeSet() = default;
  AttributeSet(const AttributeSet& other);
  AttributeSet& operator=(const AttributeSet& other);
  AttributeSet(AttributeSet&&) noexcept = default;
  AttributeSet& operator=(AttributeSet&&) noexcept = default;

  std::size_t size() const { return size_; }
  void resize(std::size_t n);
  /// Appends `count` default elements to every array.
  void push_default(std::size_t count);
  /// Reserves room for `n` elements in every array.
  void reserve(std::size_t n);
  /// Appends one element to every array: the blend of `count` existing elements.
  void push_blend(const std::uint32_t* src, const float* w, int count);
  /// Sets element `dst` of every array to the blend of `count` existing elements.
  void set_blend(std::size_t dst, const std::uint32_t* src, const float* w, int count);
  /// `set_blend3` on every array: three consecutive elements blended from three others.
  void set_blend3(std::size_t dst, std::size_t src, const float* w);
  /// `push_blend3` on every array: three elements appended, blended from `src .. src + 2`.
  void push_blend3(std::size_t src, const float* w);
  /// `push_copy` on every array: a copy of element `src` appended.
  void push_copy(std::size_t src);
  /// The batches of AttributeArrayBase on every array (one call per array for the whole batch).
  void push_blend3_batch(const std::uint32_t* triples, const float* w, std::size_t count);
  void push_blend_batch(const std::uint32_t* src, const float* w, int sources, std::size_t count);
  void push_copy_batch(const std::uint32_t* src, std::size_t count);
  /// Copies element `src` over element `dst` in every array.
  void copy(std::size_t dst, std::size_t src);
  void gather(const std::vector<std::uint32_t>& keep);
  /// A set with the same attributes holding only the elements listed, in that order: what a
  /// copy followed by `gather(keep)` gives, at the cost of `keep` rather than of the whole set.
  AttributeSet subset(const std::vector<std::uint32_t>& keep) const;
  /// Appends elements `begin .. end - 1` of the same-named arrays of `other` (which may hold
  /// more) to every array. @throws Error{InvalidArgument} when one is missing there or of
  /// another type.
  void append_from(const AttributeSet& other, std::size_t begin, std::size_t end);
  /// Swaps element `i` of every array of `other` with element `j` of the array of that name here
  /// (undo records keep old values so). @throws Error{InvalidArgument} when one is missing here.
  void swap_elements(AttributeSet& other, std::size_t i, std::size_t j);
  /// Removes array `name` and hands it over (nullptr when absent).
  std::unique_ptr<AttributeArrayBase> take(const std::string& name);
  /// Puts back an array taken by `take`. @throws Error{InvalidArgument} when `name` exists or
  /// the array's size is not the set's.
  void put(const std::string& name, std::unique_ptr<AttributeArrayBase> array);
  /// Bytes held by all arrays, room reserved included.
  std::size_t capacity_bytes() const;
  /// `release_room(keep)` on every array (AttributeArrayBase): the pages past the first `keep`
  /// elements handed back to the system, the capacity kept. Allocates nothing (a piece compacted
  /// in place calls it where allocating must not happen). Returns the bytes released.
  std::size_t release_room(std::size_t keep) noexcept;

  /// Adds an attribute. @throws Error{InvalidArgument} if `name` exists.
  template <class T>
  AttributeArray<T>& add(const std::string& name, T default_value = T()) {
    if (arrays_.count(name)) throw Error(ErrorCode::InvalidArgument, "attribute '" + name + "' already exists");
    auto array = std::make_unique<AttributeArray<T>>(default_value);
    array->resize(size_);
    auto& ref = *array;
    arrays_.emplace(name, std::move(array));
    relist();
    return ref;
  }
  /// @returns the attribute, or nullptr when absent. @throws Error{MissingAttribute} on a type mismatch.
  template <class T>
  AttributeArray<T>* find(const std::string& name) {
    auto it = arrays_.find(name);
    if (it == arrays_.end()) return nullptr;
    if (it->second->type() != typeid(T))
      throw Error(ErrorCode::MissingAttribute, "attribute '" + name + "' has another type");
    return static_cast<AttributeArray<T>*>(it->second.get());
  }
  template <class T>
  const AttributeArray<T>* find(const std::string& name) const {
    return const_cast<AttributeSet*>(this)->find<T>(name);
  }
  /// @throws Error{MissingAttribute} when absent.
  template <class T>
  AttributeArray<T>& get(const std::string& name) {
    if (auto* a = find<T>(name)) return *a;
    throw Error(ErrorCode::MissingAttribute, "attribute '" + name + "' is missing");
  }
  template <class T>
  const AttributeArray<T>& get(const std::string& name) const {
    return const_cast<AttributeSet*>(this)->get<T>(name);
  }
  bool contains(const std::string& name) const { return arrays_.count(name) != 0; }
  void remove(const std::string& name) {
    arrays_.erase(name);
    relist();
  }
  std::vector<std::string> names() const;
  const AttributeArrayBase* base(const std::string& name) const;
  AttributeArrayBase* base(const std::string& name);

  /// True if element `i` and element `j` are bitwise equal in every array (seam detection).
  bool elements_equal(std::size_t i, std::size_t j) const;

 private:
  // `list_` from `arrays_`, after every change of which arrays there are.
  void relist();

  std::map<std::string, std::unique_ptr<AttributeArrayBase>> arrays_;
  // The arrays in name order, as a flat list: the per-element calls go through it, not the map.
  std::vector<AttributeArrayBase*> list_;
  std::size_t size_ = 0;
};

}  // namespace deepcut

// SPDX-License-Identifier: MIT
#include "deepcut/core/attributes.h"

#include <algorithm>
#include <cstring>
#include <typeinfo>
#include <vector>

namespace deepcut {

std::string attr::uv_name(int set) { return "c:uv" + std::to_string(set); }
std::string attr::morph_position_name(int target) { return "v:morph" + std::to_string(target) + ":position"; }
std::string attr::morph_normal_name(int target) { return "c:morph" + std::to_string(target) + ":normal"; }
std::string attr::morph_tangent_name(int target) { return "c:morph" + std::to_string(target) + ":tangent"; }

AttributeSet::AttributeSet(const AttributeSet& other) : size_(other.size_) {
  for (const auto& [name, array] : other.arrays_) arrays_.emplace(name, array->clone());
  relist();
}

void AttributeSet::relist() {
  list_.clear();
  for (const auto& entry : arrays_) list_.push_back(entry.second.get());
}

AttributeSet& AttributeSet::operator=(const AttributeSet& other) {
  if (this != &other) {
    AttributeSet copy(other);
    *this = std::move(copy);
  }
  return *this;
}

void AttributeSet::resize(std::size_t n) {
  for (AttributeArrayBase* array : list_) array->resize(n);
  size_ = n;
}

void AttributeSet::reserve(std::size_t n) {
  for (AttributeArrayBase* array : list_) array->reserve(n);
}

void AttributeSet::push_default(std::size_t count) {
  for (AttributeArrayBase* array : list_) array->push_default(count);
  size_ += count;
}

void AttributeSet::push_blend(const std::uint32_t* src, const float* w, int count) {
  for (AttributeArrayBase* array : list_) array->push_blend(src, w, count);
  ++size_;
}

void AttributeSet::set_blend(std::size_t dst, const std::uint32_t* src, const float* w, int count) {
  for (AttributeArrayBase* array : list_) array->set_blend(dst, src, w, count);
}

void AttributeSet::set_blend3(std::size_t dst, std::size_t src, const float* w) {
  for (AttributeArrayBase* array : list_) array->set_blend3(dst, src, w);
}

void AttributeSet::push_blend3(std::size_t src, const float* w) {
  for (AttributeArrayBase* array : list_) array->push_blend3(src, w);
  size_ += 3;
}

void AttributeSet::push_copy(std::size_t src) {
  for (AttributeArrayBase* array : list_) array->push_copy(src);
  ++size_;
}

namespace {

// Fewest new elements per array for a batch to run its arrays side by side: below it the pool's
// wake-up and join cost about what the arrays' work does (a cut of 4M triangles appends about
// 17k corners and 4k vertices a batch, one of 25k about 1.4k corners and 300 vertices).
constexpr std::size_t kMinParallelBatch = 2048;

// `fn(array)` for every array of `list`, each appending `count` elements to its `size`. A large
// batch runs the arrays as tasks of their own (a cut's new corners read their parents' corners
// all over the arrays: a cache miss per face and array, taken by each array's thread at once):
// each array still appends its elements in order, so the results are the same. Its growth is
// made first, on the calling thread (room_for, as the array's batch would make it): the memory
// then comes from the caller's heap, whichever thread fills it. When an array throws, every
// array is cut back to `size` before the exception goes on: the others may have appended.
template <class Fn>
void each_array(const std::vector<AttributeArrayBase*>& list, std::size_t size, std::size_t count,
                const Fn& fn) {
  try {
    if (count < kMinParallelBatch || list.size() < 2) {
      for (AttributeArrayBase* array : list) fn(*array);
      return;
    }
    for (AttributeArrayBase* array : list) array->room_for(count);
    detail::run_chunks(list.size(), [&](std::size_t i) { fn(*list[i]); });
  } catch (...) {
    for (AttributeArrayBase* array : list)
      if (array->size() > size) array->resize(size);
    throw;
  }
}

}  // namespace

void AttributeSet::push_blend3_batch(const std::uint32_t* triples, const float* w, std::size_t count) {
  each_array(list_, size_, 3 * count,
             [&](AttributeArrayBase& array) { array.push_blend3_batch(triples, w, count); });
  size_ += 3 * count;
}

namespace {

// AttributeArray::push_blend_batch for an array of type T and kSources sources (constants, so
// the loops over sources and components unroll): the same rule, ((0 + a0 w0) + a1 w1) + a2 w2
// in each component of a floating type, the element of the largest weight (the first of equal
// ones) for others, and the same growth. False, changing nothing, when the array is not a T.
template <class T, bool kFloating, int kSources>
bool push_blend_as(AttributeArrayBase& base, const std::uint32_t* src, const float* w, std::size_t count) {
  if (base.type() != typeid(T)) return false;
  AttributeArray<T>& array = static_cast<AttributeArray<T>&>(base);
  array.room_for(count);
  std::vector<T>& data = array.data();
  const T* at = data.data();  // the room is there: appending moves nothing
  for (std::size_t i = 0; i < count; ++i, src += kSources, w += kSources) {
    if constexpr (kFloating) {
      T out = T(0);
      for (int k = 0; k < kSources; ++k) out += at[src[k]] * w[k];
      data.push_back(out);
    } else {
      int best = 0;
      for (int k = 1; k < kSources; ++k)
        if (w[k] > w[best]) best = k;
      data.push_back(at[src[best]]);
    }
  }
  return true;
}

template <int kSources>
bool push_blend_known(AttributeArrayBase& array, const std::uint32_t* src, const float* w,
                      std::size_t count) {
  return push_blend_as<glm::vec3, true, kSources>(array, src, w, count) ||
         push_blend_as<glm::vec4, true, kSources>(array, src, w, count) ||
         push_blend_as<glm::vec2, true, kSources>(array, src, w, count) ||
         push_blend_as<float, true, kSources>(array, src, w, count) ||
         push_blend_as<glm::u16vec4, false, kSources>(array, src, w, count) ||
         push_blend_as<glm::u8vec4, false, kSources>(array, src, w, count);
}

}  // namespace

void AttributeSet::push_blend_batch(const std::uint32_t* src, const float* w, int sources, std::size_t count) {
  // The attribute types a mesh holds, with one and two sources (copies, edge splits), blended
  // here with the type and the count known; anything else by the array itself.
  each_array(list_, size_, count, [&](AttributeArrayBase& array) {
    const bool done = (sources == 2 && push_blend_known<2>(array, src, w, count)) ||
                      (sources == 1 && push_blend_known<1>(array, src, w, count));
    if (!done) array.push_blend_batch(src, w, sources, count);
  });
  size_ += count;
}

void AttributeSet::push_copy_batch(const std::uint32_t* src, std::size_t count) {
  each_array(list_, size_, count, [&](AttributeArrayBase& array) { array.push_copy_batch(src, count); });
  size_ += count;
}

void AttributeSet::copy(std::size_t dst, std::size_t src) {
  for (AttributeArrayBase* array : list_) array->copy(dst, src);
}

void AttributeSet::gather(const std::vector<std::uint32_t>& keep) {
  for (AttributeArrayBase* array : list_) array->gather(keep);
  size_ = keep.size();
}

AttributeSet AttributeSet::subset(const std::vector<std::uint32_t>& keep) const {
  AttributeSet out;
  for (const auto& [name, array] : arrays_) out.arrays_.emplace(name, array->clone_subset(keep));
  out.relist();
  out.size_ = keep.size();
  return out;
}

void AttributeSet::append_from(const AttributeSet& other, std::size_t begin, std::size_t end) {
  for (auto& [name, array] : arrays_) {
    const AttributeArrayBase* from = other.base(name);
    if (!from) throw Error(ErrorCode::InvalidArgument, "append_from: no attribute '" + name + "'");
    array->append_from(*from, begin, end);
  }
  size_ += end - begin;
}

void AttributeSet::swap_elements(AttributeSet& other, std::size_t i, std::size_t j) {
  for (auto& [name, array] : other.arrays_) {
    auto it = arrays_.find(name);
    if (it == arrays_.end()) throw Error(ErrorCode::InvalidArgument, "swap_elements: no attribute '" + name + "'");
    array->swap_element(j, *it->second, i);
  }
}

std::unique_ptr<AttributeArrayBase> AttributeSet::take(const std::string& name) {
  auto it = arrays_.find(name);
  if (it == arrays_.end()) return nullptr;
  std::unique_ptr<AttributeArrayBase> out = std::move(it->second);
  arrays_.erase(it);
  relist();
  return out;
}

void AttributeSet::put(const std::string& name, std::unique_ptr<AttributeArrayBase> array) {
  if (!array || arrays_.count(name) || array->size() != size_)
    throw Error(ErrorCode::InvalidArgument, "put: attribute '" + name + "' exists or has another size");
  arrays_.emplace(name, std::move(array));
  relist();
}

std::size_t AttributeSet::capacity_bytes() const {
  std::size_t out = 0;
  for (const auto& entry : arrays_) out += entry.second->capacity_bytes();
  return out;
}

std::size_t AttributeSet::release_room(std::size_t keep) noexcept {
  std::size_t out = 0;
  for (AttributeArrayBase* array : list_) out += array->release_room(keep);
  return out;
}

std::vector<std::string> AttributeSet::names() const {
  std::vector<std::string> out;
  out.reserve(arrays_.size());
  for (const auto& entry : arrays_) out.push_back(entry.first);
  return out;
}

const AttributeArrayBase* AttributeSet::base(const std::string& name) const {
  auto it = arrays_.find(name);
  return it == arrays_.end() ? nullptr : it->second.get();
}

AttributeArrayBase* AttributeSet::base(const std::string& name) {
  auto it = arrays_.find(name);
  return it == arrays_.end() ? nullptr : it->second.get();
}

bool AttributeSet::elements_equal(std::size_t i, std::size_t j) const {
  for (const auto& entry : arrays_) {
    const auto& a = *entry.second;
    if (std::memcmp(a.element_data(i), a.element_data(j), a.element_bytes()) != 0) return false;
  }
  return true;
}

}  // namespace deepcut

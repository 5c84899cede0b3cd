// SPDX-License-Identifier: MIT
// glTF import: KHR_draco_mesh_compression. Each compressed primitive's bufferView is decoded with
// libdraco; its indices and the attributes the extension names become new accessors over new
// buffers, in the component type the file's accessors declare (so `normalized` means what it
// says), and the primitive is pointed at them. Attributes the extension does not name, and morph
// targets, stay plain accessors in the decoded vertex order, as the extension specifies. Counts
// are cross-checked with the file's accessors and the decoded size is charged to the reader's
// decode budget before anything is copied.
#include <cstring>
#include <limits>
#include <memory>

#include <draco/compression/decode.h>

#include "io/gltf_common.h"
#include "io/gltf_reader.h"

namespace deepcut::gltf_detail {
namespace {

using nlohmann::json;

constexpr const char* kDraco = "KHR_draco_mesh_compression";

int type_components(int type) {
  switch (type) {
    case TINYGLTF_TYPE_SCALAR: return 1;
    case TINYGLTF_TYPE_VEC2: return 2;
    case TINYGLTF_TYPE_VEC3: return 3;
    case TINYGLTF_TYPE_VEC4: return 4;
    default: return 0;
  }
}

// Copies every point's value of `att` as `comps` values of T (draco converts and, for a
// normalised attribute read as floats, scales). False when a point maps past the attribute.
template <class T>
bool copy_values(const draco::PointAttribute& att, std::size_t points, int comps, std::vector<unsigned char>& out) {
  std::vector<T> values(static_cast<std::size_t>(comps));
  for (std::size_t p = 0; p < points; ++p) {
    const draco::AttributeValueIndex avi = att.mapped_index(draco::PointIndex(static_cast<std::uint32_t>(p)));
    if (avi.value() >= att.size()) return false;
    if (!att.ConvertValue<T>(avi, static_cast<std::int8_t>(comps), values.data())) return false;
    std::memcpy(out.data() + p * sizeof(T) * std::size_t(comps), values.data(), sizeof(T) * std::size_t(comps));
  }
  return true;
}

bool copy_attribute(const draco::PointAttribute& att, std::size_t points, int comps, int component_type,
                    std::vector<unsigned char>& out) {
  switch (component_type) {
    case kByte: return copy_values<std::int8_t>(att, points, comps, out);
    case kUnsignedByte: return copy_values<std::uint8_t>(att, points, comps, out);
    case kShort: return copy_values<std::int16_t>(att, points, comps, out);
    case kUnsignedShort: return copy_values<std::uint16_t>(att, points, comps, out);
    case kUnsignedInt: return copy_values<std::uint32_t>(att, points, comps, out);
    case kFloat: return copy_values<float>(att, points, comps, out);
    default: return false;
  }
}

// The mesh's triangles as `isize`-byte indices (little endian) into `out`: 0, or 1 + the first
// index that is past the points or does not fit in `isize` bytes.
std::uint64_t copy_indices(const draco::Mesh& mesh, int isize, std::vector<unsigned char>& out) {
  const std::uint64_t limit = isize == 1 ? 0xFFu : isize == 2 ? 0xFFFFu : 0xFFFFFFFFu;
  for (std::uint32_t f = 0; f < mesh.num_faces(); ++f)
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t index = mesh.face(draco::FaceIndex(f))[k].value();
      if (index >= mesh.num_points() || index > limit) return std::uint64_t(index) + 1;
      std::memcpy(out.data() + (3 * std::size_t(f) + std::size_t(k)) * std::size_t(isize), &index, std::size_t(isize));
    }
  return 0;
}

}  // namespace

void Reader::decode_draco_primitives() {
  if (!raw_.contains("meshes")) return;
  const json& meshes = raw_["meshes"];
  for (std::size_t m = 0; m < meshes.size() && m < gltf_.meshes.size(); ++m) {
    const json& rm = meshes[m];
    if (!rm.is_object() || !rm.contains("primitives") || !rm["primitives"].is_array()) continue;
    for (std::size_t p = 0; p < rm["primitives"].size() && p < gltf_.meshes[m].primitives.size(); ++p) {
      const json& rp = rm["primitives"][p];
      if (!rp.is_object() || !rp.contains("extensions") || !rp["extensions"].is_object() || !rp["extensions"].contains(kDraco))
        continue;
      const std::string where = "mesh " + std::to_string(m) + " primitive " + std::to_string(p) + " (" + kDraco + ")";
      decode_draco_primitive(rp, gltf_.meshes[m].primitives[p], where);
    }
  }
}

void Reader::decode_draco_primitive(const json& raw_prim, tinygltf::Primitive& prim, const std::string& where) {
  const json& ext = raw_prim["extensions"][kDraco];
  const std::unique_ptr<draco::Mesh> mesh = decode_draco_mesh(draco_bytes(ext, prim, where), where);
  decode_draco_indices(raw_prim, prim, *mesh, where);
  for (const auto& [name, id] : ext["attributes"].items()) {
    auto it = prim.attributes.find(name);
    if (it == prim.attributes.end())
      fail(where + " attribute " + name + ": the primitive has no such attribute");
    it->second = decode_draco_attribute(*mesh, id, it->second, where + " attribute " + name);
  }
}

// The compressed bytes the extension `ext` of `prim` names, checked with the extension.
ByteSpan Reader::draco_bytes(const json& ext, const tinygltf::Primitive& prim, const std::string& where) {
  if (!ext.is_object() || !ext.contains("bufferView") || !ext["bufferView"].is_number_integer())
    fail(where + ": 'bufferView' is missing or not a number");
  if (!ext.contains("attributes") || !ext["attributes"].is_object()) fail(where + ": 'attributes' is missing or not an object");
  if (prim.mode != TINYGLTF_MODE_TRIANGLES && prim.mode != TINYGLTF_MODE_TRIANGLE_STRIP && prim.mode != -1)
    fail(where + ": mode " + std::to_string(prim.mode) + " cannot be Draco compressed (TRIANGLES or TRIANGLE_STRIP only)");
  const auto view_index = ext["bufferView"].get<std::int64_t>();
  if (view_index < 0 || view_index > std::numeric_limits<int>::max()) fail(where + ": bufferView " + std::to_string(view_index) + " does not exist");
  const int view = static_cast<int>(view_index);
  const std::size_t size = view < static_cast<int>(gltf_.bufferViews.size()) ? gltf_.bufferViews[view].byteLength : 0;
  const unsigned char* data = view_bytes(view, 0, 1, size, size > 0 ? 1 : 0, where);
  if (size == 0) fail(where + ": bufferView " + std::to_string(view) + " is empty");
  return {data, size};
}

// The triangle mesh Draco decodes from `bytes`, of a plausible size.
std::unique_ptr<draco::Mesh> Reader::decode_draco_mesh(ByteSpan bytes, const std::string& where) {
  draco::DecoderBuffer buffer;
  buffer.Init(reinterpret_cast<const char*>(bytes.data), bytes.size);
  const auto type = draco::Decoder::GetEncodedGeometryType(&buffer);
  if (!type.ok()) fail(where + ": not Draco data (" + type.status().error_msg_string() + ")");
  if (type.value() != draco::TRIANGULAR_MESH) fail(where + ": the Draco data is a point cloud, not a triangle mesh");
  draco::Decoder decoder;
  auto decoded = decoder.DecodeMeshFromBuffer(&buffer);
  if (!decoded.ok() || !decoded.value()) fail(where + ": the Draco data could not be decoded (" + decoded.status().error_msg_string() + ")");
  std::unique_ptr<draco::Mesh> mesh = std::move(decoded).value();
  const std::size_t points = mesh->num_points(), faces = mesh->num_faces();
  if (points > (std::size_t(1) << 28) || faces > (std::size_t(1) << 28))
    fail(where + ": the Draco data decodes to " + std::to_string(points) + " vertices and " + std::to_string(faces) +
         " triangles, implausibly many");
  return mesh;
}

// Indices: the accessor's own component type when it has one, else 32-bit. tinygltf was given
// the primitive without them (stand_in_for_tinygltf). `prim` gets them as a new accessor.
void Reader::decode_draco_indices(const json& raw_prim, tinygltf::Primitive& prim, const draco::Mesh& mesh,
                                  const std::string& where) {
  const std::size_t points = mesh.num_points(), faces = mesh.num_faces();
  if (raw_prim.contains("indices")) {
    if (!raw_prim["indices"].is_number_integer() || raw_prim["indices"].get<std::int64_t>() < 0 ||
        raw_prim["indices"].get<std::int64_t>() > std::numeric_limits<int>::max())
      fail(where + ": 'indices' is not an accessor index");
    prim.indices = raw_prim["indices"].get<int>();
  }
  int component_type = kUnsignedInt;
  if (prim.indices >= 0) {
    if (static_cast<std::size_t>(prim.indices) >= gltf_.accessors.size())
      fail(where + ": indices accessor " + std::to_string(prim.indices) + " does not exist");
    const auto& acc = gltf_.accessors[prim.indices];
    if (acc.count != 3 * faces)
      fail(where + ": Draco decodes " + std::to_string(3 * faces) + " indices, accessor " +
           std::to_string(prim.indices) + " says " + std::to_string(acc.count));
    component_type = acc.componentType;
  }
  const int isize = component_size(component_type);
  if (isize == 0 || component_type == kFloat || component_type == kByte || component_type == kShort)
    fail(where + ": indices have componentType " + std::to_string(component_type));
  spend_decode_budget(3 * faces * std::size_t(isize), where);
  std::vector<unsigned char> bytes(3 * faces * std::size_t(isize));
  const std::uint64_t bad = copy_indices(mesh, isize, bytes);
  if (bad != 0)
    fail(where + ": Draco index " + std::to_string(bad - 1) + " is past the " + std::to_string(points) +
         " vertices");
  tinygltf::Accessor acc;
  acc.componentType = component_type;
  acc.type = TINYGLTF_TYPE_SCALAR;
  acc.count = 3 * faces;
  prim.indices = add_decoded_accessor(acc, std::move(bytes));
  prim.mode = TINYGLTF_MODE_TRIANGLES;
}

// Attribute `id` of `mesh` as a new accessor like `accessor` (its type, component type and
// normalisation) over a new view; fails unless the counts and components agree.
int Reader::decode_draco_attribute(const draco::Mesh& mesh, const json& id, int accessor, const std::string& what) {
  const std::size_t points = mesh.num_points();
  if (!id.is_number_integer()) fail(what + ": its Draco id is not a number");
  const auto uid = id.get<std::int64_t>();
  const draco::PointAttribute* att =
      uid >= 0 && uid <= std::numeric_limits<std::uint32_t>::max() ? mesh.GetAttributeByUniqueId(static_cast<std::uint32_t>(uid)) : nullptr;
  if (!att) fail(what + ": the Draco data has no attribute with id " + std::to_string(uid));
  if (accessor < 0 || static_cast<std::size_t>(accessor) >= gltf_.accessors.size())
    fail(what + ": accessor " + std::to_string(accessor) + " does not exist");
  tinygltf::Accessor acc = gltf_.accessors[accessor];
  const int comps = type_components(acc.type), csize = component_size(acc.componentType);
  if (comps == 0 || csize == 0) fail(what + ": accessor " + std::to_string(accessor) + " has an unusable type");
  if (acc.count != points)
    fail(what + ": Draco decodes " + std::to_string(points) + " vertices, accessor " + std::to_string(accessor) + " says " +
         std::to_string(acc.count));
  if (att->num_components() != comps)
    fail(what + ": Draco stores " + std::to_string(int(att->num_components())) + " components, the accessor " + std::to_string(comps));
  const std::size_t bytes_needed = points * std::size_t(comps) * std::size_t(csize);
  spend_decode_budget(bytes_needed, what);
  std::vector<unsigned char> bytes(bytes_needed);
  if (!copy_attribute(*att, points, comps, acc.componentType, bytes)) fail(what + ": the Draco values could not be read");
  return add_decoded_accessor(acc, std::move(bytes));
}

int Reader::add_decoded_accessor(tinygltf::Accessor acc, std::vector<unsigned char> bytes) {
  tinygltf::BufferView view;
  view.byteLength = bytes.size();
  view.buffer = add_decoded_buffer(std::move(bytes));
  gltf_.bufferViews.push_back(view);
  acc.bufferView = static_cast<int>(gltf_.bufferViews.size() - 1);
  acc.byteOffset = 0;
  acc.sparse.isSparse = false;
  gltf_.accessors.push_back(acc);
  return static_cast<int>(gltf_.accessors.size() - 1);
}

}  // namespace deepcut::gltf_detail

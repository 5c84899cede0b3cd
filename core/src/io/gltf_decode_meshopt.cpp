// SPDX-License-Identifier: MIT
// glTF import: EXT_meshopt_compression. Each compressed buffer view is decoded (libmeshoptimizer:
// ATTRIBUTES with the OCTAHEDRAL, QUATERNION and EXPONENTIAL filters, TRIANGLES, INDICES) into a
// buffer of its own, and the view is pointed at it, so accessors, sparse data and images read it
// as plain bytes. Every parameter is checked before the library sees it (its asserts are not
// error handling) and the decoded size is charged to the reader's decode budget first.
#include <cstring>
#include <limits>

#include <meshoptimizer.h>

#include "io/gltf_reader.h"

namespace deepcut::gltf_detail {
namespace {

using nlohmann::json;

constexpr const char* kMeshopt = "EXT_meshopt_compression";
constexpr std::size_t kMaxCount = std::size_t(1) << 28;

// The extension object of `o`, or nullptr.
const json* meshopt_of(const json& o) {
  if (!o.is_object() || !o.contains("extensions") || !o["extensions"].is_object()) return nullptr;
  const json& e = o["extensions"];
  return e.contains(kMeshopt) ? &e[kMeshopt] : nullptr;
}

// The parameters of one compressed view, checked against the spec's rules.
struct MeshoptView {
  std::size_t buffer = 0, offset = 0, length = 0, stride = 0, count = 0;
  std::string mode, filter = "NONE";
};

// The parameters of `ext` (a bufferView's extension object), checked against the spec's rules,
// each one a precondition of the library; `fail` throws.
template <class Fail>
MeshoptView parse_meshopt(const json& ext, const std::string& what, Fail&& fail) {
  MeshoptView m;
  auto number = [&](const char* key, bool required, std::size_t fallback) -> std::size_t {
    if (!ext.contains(key)) {
      if (required) fail(what + ": '" + key + "' is missing");
      return fallback;
    }
    const json& n = ext[key];
    if (!n.is_number_unsigned() || n.get<std::uint64_t>() > std::numeric_limits<std::uint32_t>::max())
      fail(what + ": '" + key + "' is not a whole number below 2^32");
    return static_cast<std::size_t>(n.get<std::uint64_t>());
  };
  auto text = [&](const char* key, const std::string& fallback) {
    if (!ext.contains(key)) return fallback;
    if (!ext[key].is_string()) fail(what + ": '" + key + "' is not a string");
    return ext[key].get<std::string>();
  };
  m.buffer = number("buffer", true, 0);
  m.offset = number("byteOffset", false, 0);
  m.length = number("byteLength", true, 0);
  m.stride = number("byteStride", true, 0);
  m.count = number("count", true, 0);
  m.mode = text("mode", "");
  m.filter = text("filter", "NONE");

  // The spec's rules.
  if (m.mode != "ATTRIBUTES" && m.mode != "TRIANGLES" && m.mode != "INDICES")
    fail(what + ": mode '" + m.mode + "' is not ATTRIBUTES, TRIANGLES or INDICES");
  if (m.mode == "ATTRIBUTES" && (m.stride == 0 || m.stride % 4 != 0 || m.stride > 256))
    fail(what + ": byteStride " + std::to_string(m.stride) + " must be a multiple of 4 up to 256 for ATTRIBUTES");
  if (m.mode != "ATTRIBUTES" && m.stride != 2 && m.stride != 4)
    fail(what + ": byteStride " + std::to_string(m.stride) + " must be 2 or 4 for " + m.mode);
  if (m.mode == "TRIANGLES" && m.count % 3 != 0) fail(what + ": count " + std::to_string(m.count) + " is not a multiple of 3");
  if (m.filter != "NONE" && m.mode != "ATTRIBUTES") fail(what + ": filter " + m.filter + " needs mode ATTRIBUTES");
  if (m.filter == "OCTAHEDRAL" && m.stride != 4 && m.stride != 8)
    fail(what + ": filter OCTAHEDRAL needs byteStride 4 or 8, not " + std::to_string(m.stride));
  if (m.filter == "QUATERNION" && m.stride != 8) fail(what + ": filter QUATERNION needs byteStride 8, not " + std::to_string(m.stride));
  if (m.filter != "NONE" && m.filter != "OCTAHEDRAL" && m.filter != "QUATERNION" && m.filter != "EXPONENTIAL")
    fail(what + ": unknown filter '" + m.filter + "'");
  return m;
}

}  // namespace

bool stand_in_for_tinygltf(const json& doc, bool glb, json* patched) {
  json& patched_doc = *patched;
  bool changed = false;
  if (doc.contains("meshes") && doc["meshes"].is_array())
    for (std::size_t m = 0; m < doc["meshes"].size(); ++m) {
      const json& mesh = doc["meshes"][m];
      if (!mesh.is_object() || !mesh.contains("primitives") || !mesh["primitives"].is_array()) continue;
      for (std::size_t p = 0; p < mesh["primitives"].size(); ++p) {
        const json& prim = mesh["primitives"][p];
        if (!prim.is_object() || !prim.contains("indices") || !prim.contains("extensions") || !prim["extensions"].is_object() ||
            !prim["extensions"].contains("KHR_draco_mesh_compression"))
          continue;
        if (!changed) patched_doc = doc;
        changed = true;
        patched_doc["meshes"][m]["primitives"][p].erase("indices");
      }
    }
  const json empty = json::array();
  const json& buffers = doc.contains("buffers") && doc["buffers"].is_array() ? doc["buffers"] : empty;
  for (std::size_t b = 0; b < buffers.size(); ++b) {
    const json* ext = meshopt_of(buffers[b]);
    if (!ext || !ext->is_object() || !ext->contains("fallback") || !(*ext)["fallback"].is_boolean() ||
        !(*ext)["fallback"].get<bool>() || buffers[b].contains("uri") || (glb && b == 0))
      continue;
    if (!changed) patched_doc = doc;
    changed = true;
    patched_doc["buffers"][b]["uri"] = "data:application/octet-stream;base64,AAAA";
    patched_doc["buffers"][b]["byteLength"] = 3;
  }
  return changed;
}

std::vector<unsigned char> glb_with_json(const unsigned char* glb, std::size_t size, std::string json_text, bool bin_stand_in) {
  // The container was checked by parse_container: header, JSON chunk, optional BIN chunk.
  std::uint32_t header[5];
  std::memcpy(header, glb, 20);
  const std::size_t rest = 20 + ((std::size_t(header[3]) + 3) & ~std::size_t(3));
  const std::size_t end = std::min<std::size_t>(header[2], size);
  while (json_text.size() % 4) json_text += ' ';
  std::vector<unsigned char> out(glb, glb + 12);
  auto put32 = [&](std::size_t at, std::size_t v) {
    for (int i = 0; i < 4; ++i) out[at + std::size_t(i)] = static_cast<unsigned char>(v >> (8 * i));
  };
  out.resize(20);
  put32(12, json_text.size());
  put32(16, 0x4E4F534Au);
  out.insert(out.end(), json_text.begin(), json_text.end());
  if (bin_stand_in) {
    const unsigned char chunk[12] = {4, 0, 0, 0, 'B', 'I', 'N', 0, 0, 0, 0, 0};
    out.insert(out.end(), chunk, chunk + 12);
  } else if (rest < end) {
    out.insert(out.end(), glb + rest, glb + end);
  }
  put32(8, out.size());
  return out;
}

void Reader::spend_decode_budget(std::size_t bytes, const std::string& what) {
  if (bytes > decode_left_)
    fail(what + ": decoding " + std::to_string(bytes) + " bytes would take the model past its decode limit; the file claims " +
         "far more data than it holds");
  decode_left_ -= bytes;
}

int Reader::add_decoded_buffer(std::vector<unsigned char> bytes) {
  tinygltf::Buffer buffer;
  buffer.data = std::move(bytes);
  gltf_.buffers.push_back(std::move(buffer));
  return static_cast<int>(gltf_.buffers.size() - 1);
}

void Reader::decode_meshopt_views() {
  if (!raw_.contains("bufferViews")) return;
  const json& views = raw_["bufferViews"];
  for (std::size_t v = 0; v < views.size() && v < gltf_.bufferViews.size(); ++v) {
    const json* ext = meshopt_of(views[v]);
    if (!ext) continue;
    const std::string what = "bufferView " + std::to_string(v) + " (" + kMeshopt + ")";
    if (!ext->is_object()) fail(what + ": the extension is not an object");
    const MeshoptView m = parse_meshopt(*ext, what, [&](const std::string& msg) { fail(msg); });
    if (m.count > kMaxCount) fail(what + ": count " + std::to_string(m.count) + " is implausibly large");
    const std::size_t decoded = m.count * m.stride;  // <= 2^28 * 256
    const auto& parent = gltf_.bufferViews[v];
    if (parent.byteLength != decoded)
      fail(what + ": count " + std::to_string(m.count) + " x byteStride " + std::to_string(m.stride) + " = " +
           std::to_string(decoded) + " bytes, but the bufferView is " + std::to_string(parent.byteLength) + " bytes long");
    if (parent.byteStride != 0 && m.mode == "ATTRIBUTES" && parent.byteStride != m.stride)
      fail(what + ": byteStride " + std::to_string(m.stride) + " differs from the bufferView's " +
           std::to_string(parent.byteStride));
    if (m.buffer >= gltf_.buffers.size()) fail(what + ": buffer " + std::to_string(m.buffer) + " does not exist");
    const ByteSpan source = buffer_bytes(m.buffer);
    if (m.offset > source.size || m.length > source.size - m.offset)
      fail(what + ": its " + std::to_string(m.length) + " compressed bytes at offset " + std::to_string(m.offset) +
           " run past the end of buffer " + std::to_string(m.buffer) + " (" + std::to_string(source.size) + " bytes)");
    spend_decode_budget(decoded, what);

    std::vector<unsigned char> out(decoded);
    const unsigned char* in = source.data + m.offset;
    int rc = 0;
    if (m.count == 0) rc = 0;
    else if (m.mode == "ATTRIBUTES") rc = meshopt_decodeVertexBuffer(out.data(), m.count, m.stride, in, m.length);
    else if (m.mode == "TRIANGLES") rc = meshopt_decodeIndexBuffer(out.data(), m.count, m.stride, in, m.length);
    else rc = meshopt_decodeIndexSequence(out.data(), m.count, m.stride, in, m.length);
    if (rc != 0) fail(what + ": the " + m.mode + " data could not be decoded (meshoptimizer error " + std::to_string(rc) + ")");
    if (m.filter == "OCTAHEDRAL") meshopt_decodeFilterOct(out.data(), m.count, m.stride);
    else if (m.filter == "QUATERNION") meshopt_decodeFilterQuat(out.data(), m.count, m.stride);
    else if (m.filter == "EXPONENTIAL") meshopt_decodeFilterExp(out.data(), m.count, m.stride);

    const int decoded_buffer = add_decoded_buffer(std::move(out));
    auto& view = gltf_.bufferViews[v];
    view.buffer = decoded_buffer;
    view.byteOffset = 0;
  }
}

}  // namespace deepcut::gltf_detail

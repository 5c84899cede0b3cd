// SPDX-License-Identifier: MIT
// glTF export, compressed: the pass that turns the writer's document into a KHR_draco_mesh_compression
// or EXT_meshopt_compression one (see gltf_write_compress.h). The buffer is split into its views,
// Draco replaces each primitive's attribute and index views by one compressed view, meshopt
// replaces eligible views by compressed payloads with a fallback buffer, and the views are joined
// again into one binary buffer.
#include "io/gltf_write_compress.h"

#include <draco/compression/decode.h>
#include <draco/compression/encode.h>
#include <meshoptimizer.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <memory>

#include "deepcut/core/errors.h"
#include "io/gltf_common.h"

namespace deepcut {

bool parse_compression(const std::string& name, Compression* out) {
  if (name == "none") *out = Compression::None;
  else if (name == "draco") *out = Compression::Draco;
  else if (name == "meshopt") *out = Compression::Meshopt;
  else return false;
  return true;
}

namespace gltf_detail {
namespace {

using nlohmann::json;

constexpr const char* kDraco = "KHR_draco_mesh_compression";
constexpr const char* kMeshopt = "EXT_meshopt_compression";

// One buffer view: its bytes, and for a meshopt compressed view the payload that replaces them.
struct View {
  std::vector<unsigned char> bytes;
  std::vector<unsigned char> payload;  // empty: stored plain
  std::size_t stride = 0, count = 0;
  const char* mode = nullptr;
};

struct Doc {
  json& doc;
  std::vector<View> views;

  [[noreturn]] void fail(const std::string& what) const { throw Error(ErrorCode::InvariantViolated, what); }
  std::size_t element_size(const json& acc) const {
    return std::size_t(component_count(acc.value("type", ""))) * std::size_t(component_size(acc.value("componentType", 0)));
  }
  // An accessor's elements packed tightly; the writer's own accessors, so bounds are invariants.
  std::vector<unsigned char> packed(const json& acc) const {
    const std::size_t elem = element_size(acc), count = acc.value("count", std::size_t(0));
    const View& v = views.at(acc["bufferView"].get<std::size_t>());
    const std::size_t stride = doc["bufferViews"][acc["bufferView"].get<std::size_t>()].value("byteStride", elem);
    const std::size_t offset = acc.value("byteOffset", std::size_t(0));
    if (count > 0 && offset + (count - 1) * stride + elem > v.bytes.size()) fail("an accessor runs past its buffer view");
    std::vector<unsigned char> out(count * elem);
    for (std::size_t i = 0; i < count; ++i) std::memcpy(out.data() + i * elem, v.bytes.data() + offset + i * stride, elem);
    return out;
  }
  int add_view(std::vector<unsigned char> bytes) {
    doc["bufferViews"].push_back({{"buffer", 0}, {"byteOffset", 0}, {"byteLength", bytes.size()}});
    views.push_back(View{std::move(bytes), {}, 0, 0, nullptr});
    return static_cast<int>(views.size() - 1);
  }
};

draco::DataType draco_type(int component_type) {
  switch (component_type) {
    case kByte: return draco::DT_INT8;
    case kUnsignedByte: return draco::DT_UINT8;
    case kShort: return draco::DT_INT16;
    case kUnsignedShort: return draco::DT_UINT16;
    case kUnsignedInt: return draco::DT_UINT32;
    case kFloat: return draco::DT_FLOAT32;
    default: return draco::DT_INVALID;
  }
}

draco::GeometryAttribute::Type draco_semantic(const std::string& name) {
  if (name == "POSITION") return draco::GeometryAttribute::POSITION;
  if (name == "NORMAL") return draco::GeometryAttribute::NORMAL;
  if (name.rfind("TEXCOORD_", 0) == 0) return draco::GeometryAttribute::TEX_COORD;
  if (name.rfind("COLOR_", 0) == 0) return draco::GeometryAttribute::COLOR;
  return draco::GeometryAttribute::GENERIC;  // tangents, joints, weights: stored losslessly
}

// The Draco mesh of one primitive: `names[i]` becomes attribute i, one point per glTF vertex.
std::unique_ptr<draco::Mesh> build_draco_mesh(Doc& d, const json& prim, const std::vector<std::string>& names) {
  const json& accessors = d.doc["accessors"];
  auto mesh = std::make_unique<draco::Mesh>();
  const std::size_t n = accessors[prim["attributes"]["POSITION"].get<std::size_t>()]["count"].get<std::size_t>();
  mesh->set_num_points(static_cast<std::uint32_t>(n));
  for (const auto& name : names) {
    const json& acc = accessors[prim["attributes"][name].get<std::size_t>()];
    const std::size_t elem = d.element_size(acc);
    const std::vector<unsigned char> data = d.packed(acc);
    draco::GeometryAttribute ga;
    ga.Init(draco_semantic(name), nullptr, static_cast<std::uint8_t>(component_count(acc["type"].get<std::string>())),
            draco_type(acc["componentType"].get<int>()), acc.value("normalized", false), static_cast<std::int64_t>(elem), 0);
    const int id = mesh->AddAttribute(ga, true, static_cast<std::uint32_t>(n));
    if (id < 0) d.fail("Draco could not add attribute " + name);
    for (std::size_t v = 0; v < n; ++v)
      mesh->attribute(id)->SetAttributeValue(draco::AttributeValueIndex(static_cast<std::uint32_t>(v)), data.data() + v * elem);
  }
  const json& iacc = accessors[prim["indices"].get<std::size_t>()];
  const std::vector<unsigned char> idx = d.packed(iacc);
  const std::size_t isize = std::size_t(component_size(iacc["componentType"].get<int>()));
  auto index = [&](std::size_t i) {
    std::uint32_t v = 0;
    std::memcpy(&v, idx.data() + i * isize, isize);  // little endian
    return draco::PointIndex(v);
  };
  for (std::size_t t = 0; t + 2 < idx.size() / isize; t += 3) mesh->AddFace({index(t), index(t + 1), index(t + 2)});
  return mesh;
}

// True when `decoded` has the original's points in the original order (its positions within the
// quantisation of `original`'s).
bool keeps_vertex_order(const draco::Mesh& original, const draco::Mesh& decoded) {
  if (decoded.num_points() != original.num_points()) return false;
  const auto* a = original.GetNamedAttribute(draco::GeometryAttribute::POSITION);
  const auto* b = decoded.GetNamedAttribute(draco::GeometryAttribute::POSITION);
  if (!a || !b) return false;
  float lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
  std::vector<std::array<float, 3>> pa(original.num_points());
  for (std::uint32_t p = 0; p < original.num_points(); ++p) {
    a->ConvertValue<float>(a->mapped_index(draco::PointIndex(p)), 3, pa[p].data());
    for (int c = 0; c < 3; ++c) lo[c] = std::min(lo[c], pa[p][std::size_t(c)]), hi[c] = std::max(hi[c], pa[p][std::size_t(c)]);
  }
  const float extent = std::max({hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2], 0.0f});
  const float tolerance = 2.0f * extent / 16383.0f + 1e-6f;
  for (std::uint32_t p = 0; p < decoded.num_points(); ++p) {
    float q[3];
    b->ConvertValue<float>(b->mapped_index(draco::PointIndex(p)), 3, q);
    for (int c = 0; c < 3; ++c)
      if (!(std::abs(q[c] - pa[p][std::size_t(c)]) <= tolerance)) return false;
  }
  return true;
}

// The attributes of `prim` Draco compresses: those over plain views (not sparse). `plain_left`
// says whether any attribute stays plain.
std::vector<std::string> draco_attribute_names(const json& accessors, const json& prim, bool& plain_left) {
  std::vector<std::string> names;
  plain_left = false;
  for (const auto& [name, a] : prim["attributes"].items()) {
    const json& acc = accessors.at(a.get<std::size_t>());
    if (acc.contains("bufferView") && !acc.contains("sparse")) names.push_back(name);
    else plain_left = true;
  }
  return names;
}

// `mesh` Draco encoded into `encoded`, keeping its vertex order when `keep_order`.
void encode_draco(const Doc& d, const draco::Mesh& mesh, bool keep_order, draco::EncoderBuffer& encoded,
                  const std::string& where) {
  draco::Encoder encoder;
  encoder.SetAttributeQuantization(draco::GeometryAttribute::POSITION, 14);
  encoder.SetAttributeQuantization(draco::GeometryAttribute::NORMAL, 10);
  encoder.SetAttributeQuantization(draco::GeometryAttribute::TEX_COORD, 12);
  encoder.SetEncodingMethod(keep_order ? draco::MESH_SEQUENTIAL_ENCODING : draco::MESH_EDGEBREAKER_ENCODING);
  const draco::Status status = encoder.EncodeMeshToBuffer(mesh, &encoded);
  if (!status.ok()) d.fail(where + ": Draco could not encode it (" + status.error_msg_string() + ")");
}

// What a reader decodes from `encoded`: its counts and bounds are what the accessors must say.
std::unique_ptr<draco::Mesh> decode_draco(const Doc& d, const draco::EncoderBuffer& encoded,
                                          const std::string& where) {
  draco::DecoderBuffer in;
  in.Init(encoded.data(), encoded.size());
  draco::Decoder decoder;
  auto decoded = decoder.DecodeMeshFromBuffer(&in);
  if (!decoded.ok() || !decoded.value()) d.fail(where + ": Draco cannot decode what it encoded (" + decoded.status().error_msg_string() + ")");
  return std::move(decoded).value();
}

// Attribute accessor `acc`, now of the Draco data `back`: its vertex count and, for the positions
// `pos`, their bounds.
void draco_attribute_accessor(json& acc, const draco::Mesh& back, const draco::PointAttribute* pos) {
  acc.erase("bufferView");
  acc.erase("byteOffset");
  acc["count"] = back.num_points();
  if (!pos) return;
  std::array<float, 3> lo{INFINITY, INFINITY, INFINITY}, hi{-INFINITY, -INFINITY, -INFINITY};
  for (std::uint32_t p = 0; p < back.num_points(); ++p) {
    float q[3];
    pos->ConvertValue<float>(pos->mapped_index(draco::PointIndex(p)), 3, q);
    for (int c = 0; c < 3; ++c)
      lo[std::size_t(c)] = std::min(lo[std::size_t(c)], q[c]),
      hi[std::size_t(c)] = std::max(hi[std::size_t(c)], q[c]);
  }
  acc["min"] = lo;
  acc["max"] = hi;
}

// Replaces one primitive's plain indices and attributes by a Draco compressed view.
void draco_primitive(Doc& d, json& prim, const std::string& where) {
  json& accessors = d.doc["accessors"];
  if (!prim.contains("indices") || !prim["attributes"].contains("POSITION") || prim.value("mode", 4) != 4)
    return;
  bool plain_left = false;
  const std::vector<std::string> names = draco_attribute_names(accessors, prim, plain_left);
  const bool keep_order = plain_left || (prim.contains("targets") && !prim["targets"].empty());
  const auto mesh = build_draco_mesh(d, prim, names);
  draco::EncoderBuffer encoded;
  encode_draco(d, *mesh, keep_order, encoded, where);
  const std::unique_ptr<draco::Mesh> back = decode_draco(d, encoded, where);
  if (keep_order && !keeps_vertex_order(*mesh, *back))
    d.fail(where +
           ": Draco changed its vertex order, which its morph targets (plain accessors) depend on; "
           "write it with --compress meshopt or without compression");
  json ext_attributes = json::object();
  for (std::size_t i = 0; i < names.size(); ++i) {
    const std::uint32_t uid = mesh->attribute(static_cast<std::int32_t>(i))->unique_id();
    if (!back->GetAttributeByUniqueId(uid)) d.fail(where + ": Draco lost attribute " + names[i]);
    ext_attributes[names[i]] = uid;
    draco_attribute_accessor(accessors[prim["attributes"][names[i]].get<std::size_t>()], *back,
                             names[i] == "POSITION" ? back->GetAttributeByUniqueId(uid) : nullptr);
  }
  json& iacc = accessors[prim["indices"].get<std::size_t>()];
  iacc.erase("bufferView");
  iacc.erase("byteOffset");
  iacc["count"] = std::size_t(back->num_faces()) * 3;
  if (back->num_points() > 65535) iacc["componentType"] = kUnsignedInt;
  const int view = d.add_view(std::vector<unsigned char>(encoded.data(), encoded.data() + encoded.size()));
  prim["extensions"][kDraco] = {{"bufferView", view}, {"attributes", ext_attributes}};
}

// Drops the views nothing refers to any more and renumbers the references.
void prune_views(Doc& d) {
  json& doc = d.doc;
  std::vector<json*> refs;
  for (auto& acc : doc["accessors"]) {
    if (acc.contains("bufferView")) refs.push_back(&acc["bufferView"]);
    if (acc.contains("sparse")) {
      refs.push_back(&acc["sparse"]["indices"]["bufferView"]);
      refs.push_back(&acc["sparse"]["values"]["bufferView"]);
    }
  }
  if (doc.contains("images"))
    for (auto& img : doc["images"])
      if (img.contains("bufferView")) refs.push_back(&img["bufferView"]);
  if (doc.contains("meshes"))
    for (auto& mesh : doc["meshes"])
      for (auto& prim : mesh["primitives"])
        if (prim.contains("extensions") && prim["extensions"].contains(kDraco)) refs.push_back(&prim["extensions"][kDraco]["bufferView"]);
  std::vector<int> renumber(d.views.size(), -1);
  for (const json* r : refs) renumber[r->get<std::size_t>()] = 0;
  json views = json::array();
  std::vector<View> kept;
  for (std::size_t v = 0; v < d.views.size(); ++v) {
    if (renumber[v] < 0) continue;
    renumber[v] = static_cast<int>(kept.size());
    kept.push_back(std::move(d.views[v]));
    views.push_back(doc["bufferViews"][v]);
  }
  for (json* r : refs) *r = renumber[r->get<std::size_t>()];
  d.views = std::move(kept);
  doc["bufferViews"] = views;
}

// Who reads each view: `count[v]` accessors read view v (-1: something else uses it too, a
// sparse accessor or an image), the last of them `accessor[v]`.
struct ViewReaders {
  std::vector<int> count;
  std::vector<std::size_t> accessor;
};

ViewReaders view_readers(json& doc, std::size_t views) {
  ViewReaders r{std::vector<int>(views, 0), std::vector<std::size_t>(views, 0)};
  for (std::size_t a = 0; a < doc["accessors"].size(); ++a) {
    const json& acc = doc["accessors"][a];
    if (acc.contains("sparse")) {
      r.count[acc["sparse"]["indices"]["bufferView"].get<std::size_t>()] = -1;
      r.count[acc["sparse"]["values"]["bufferView"].get<std::size_t>()] = -1;
    }
    if (!acc.contains("bufferView")) continue;
    const std::size_t v = acc["bufferView"].get<std::size_t>();
    if (r.count[v] >= 0) ++r.count[v];
    r.accessor[v] = a;
  }
  if (doc.contains("images"))
    for (const auto& img : doc["images"])
      if (img.contains("bufferView")) r.count[img["bufferView"].get<std::size_t>()] = -1;
  return r;
}

// Per accessor: whether it holds a triangle list's indices.
std::vector<bool> triangle_index_accessors(json& doc) {
  std::vector<bool> index_accessor(doc["accessors"].size(), false);
  if (doc.contains("meshes"))
    for (const auto& mesh : doc["meshes"])
      for (const auto& prim : mesh["primitives"])
        if (prim.contains("indices") && prim.value("mode", 4) == 4) index_accessor[prim["indices"].get<std::size_t>()] = true;
  return index_accessor;
}

// `view`'s `count` indices of `elem` bytes each, encoded as meshopt's TRIANGLES.
void encode_meshopt_indices(View& view, std::size_t count, std::size_t elem) {
  std::vector<unsigned int> idx(count);
  unsigned int top = 0;
  for (std::size_t i = 0; i < count; ++i) {
    std::uint32_t x = 0;
    std::memcpy(&x, view.bytes.data() + i * elem, elem);
    idx[i] = x;
    top = std::max(top, x);
  }
  view.payload.resize(meshopt_encodeIndexBufferBound(count, std::size_t(top) + 1));
  view.payload.resize(meshopt_encodeIndexBuffer(view.payload.data(), view.payload.size(), idx.data(), count));
  view.mode = "TRIANGLES";
}

// Encodes view `v`, read whole by accessor `acc` alone (triangle indices when `indices`), when
// meshopt can carry it; true when it was.
bool encode_meshopt_view(Doc& d, std::size_t v, const json& acc, bool indices) {
  View& view = d.views[v];
  const std::size_t elem = d.element_size(acc), count = acc["count"].get<std::size_t>();
  const int ctype = acc["componentType"].get<int>();
  if (count == 0 || acc.value("byteOffset", std::size_t(0)) != 0 || count * elem != view.bytes.size() ||
      d.doc["bufferViews"][v].value("byteStride", elem) != elem)
    return false;
  if (indices && (ctype == kUnsignedShort || ctype == kUnsignedInt) && count % 3 == 0) {
    encode_meshopt_indices(view, count, elem);
  } else if (elem % 4 == 0 && elem <= 256) {
    view.payload.resize(meshopt_encodeVertexBufferBound(count, elem));
    view.payload.resize(
        meshopt_encodeVertexBuffer(view.payload.data(), view.payload.size(), view.bytes.data(), count, elem));
    view.mode = "ATTRIBUTES";
  } else {
    return false;
  }
  if (view.payload.empty()) d.fail("meshopt could not encode buffer view " + std::to_string(v));
  view.stride = elem;
  view.count = count;
  return true;
}

// Chooses each view meshopt can carry (read whole by one accessor) and encodes it; true when any was.
bool meshopt_views(Doc& d) {
  const ViewReaders readers = view_readers(d.doc, d.views.size());
  const std::vector<bool> index_accessor = triangle_index_accessors(d.doc);
  meshopt_encodeVertexVersion(0);
  meshopt_encodeIndexVersion(1);
  bool any = false;
  for (std::size_t v = 0; v < d.views.size(); ++v) {
    if (readers.count[v] != 1) continue;
    const std::size_t a = readers.accessor[v];
    any |= encode_meshopt_view(d, v, d.doc["accessors"][a], index_accessor[a]);
  }
  return any;
}

void add_extension(json& doc, const char* name) {
  for (const char* key : {"extensionsUsed", "extensionsRequired"}) {
    if (!doc.contains(key)) doc[key] = json::array();
    if (std::find(doc[key].begin(), doc[key].end(), name) == doc[key].end()) doc[key].push_back(name);
  }
}

// Lays the views out again: plain bytes and payloads in buffer 0, meshopt views in the fallback.
void join(Doc& d, detail::UninitVector<unsigned char>& bin, bool glb) {
  json& doc = d.doc;
  bin.clear();
  std::size_t fallback = 0;
  for (std::size_t v = 0; v < d.views.size(); ++v) {
    View& view = d.views[v];
    json& out = doc["bufferViews"][v];
    while (bin.size() % 4) bin.push_back(0);
    const std::vector<unsigned char>& stored = view.mode ? view.payload : view.bytes;
    const std::size_t at = bin.size();
    bin.insert(bin.end(), stored.begin(), stored.end());
    if (!view.mode) {
      out["byteOffset"] = at;
      continue;
    }
    out["buffer"] = 1;
    out["byteOffset"] = fallback;
    out["byteLength"] = view.bytes.size();
    out["extensions"][kMeshopt] = {{"buffer", 0}, {"byteOffset", at}, {"byteLength", stored.size()},
                                   {"byteStride", view.stride}, {"count", view.count}, {"mode", view.mode}};
    fallback += (view.bytes.size() + 3) & ~std::size_t(3);
  }
  while (bin.size() % 4) bin.push_back(0);
  json buffer = {{"byteLength", bin.size()}};
  if (!glb) buffer["uri"] = "data:application/octet-stream;base64," + base64_encode(bin.data(), bin.size());
  doc["buffers"] = json::array({buffer});
  if (fallback > 0) doc["buffers"].push_back({{"byteLength", fallback}, {"extensions", {{kMeshopt, {{"fallback", true}}}}}});
}

}  // namespace

void compress_document(json& doc, detail::UninitVector<unsigned char>& bin, Compression compression, bool glb) {
  if (compression == Compression::None || !doc.contains("bufferViews") || !doc.contains("accessors")) return;
  Doc d{doc, {}};
  for (const auto& v : doc["bufferViews"]) {
    const std::size_t offset = v.value("byteOffset", std::size_t(0)), length = v["byteLength"].get<std::size_t>();
    if (offset > bin.size() || length > bin.size() - offset) d.fail("a buffer view runs past the buffer");
    d.views.push_back(View{std::vector<unsigned char>(bin.begin() + std::ptrdiff_t(offset), bin.begin() + std::ptrdiff_t(offset + length)), {}, 0, 0, nullptr});
  }
  bool compressed = false;
  if (compression == Compression::Draco && doc.contains("meshes")) {
    for (std::size_t m = 0; m < doc["meshes"].size(); ++m)
      for (std::size_t p = 0; p < doc["meshes"][m]["primitives"].size(); ++p) {
        json& prim = doc["meshes"][m]["primitives"][p];
        draco_primitive(d, prim, "mesh " + std::to_string(m) + " primitive " + std::to_string(p));
        compressed = compressed || (prim.contains("extensions") && prim["extensions"].contains(kDraco));
      }
    prune_views(d);
    if (compressed) add_extension(doc, kDraco);
  } else if (compression == Compression::Meshopt) {
    if (meshopt_views(d)) add_extension(doc, kMeshopt);
  }
  join(d, bin, glb);
}

}  // namespace gltf_detail
}  // namespace deepcut

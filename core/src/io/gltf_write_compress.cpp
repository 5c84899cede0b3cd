// SPDX-License-Identifier: MIT
// glTF export, compressed: the pass that turns the writer's document into a KHR_draco_mesh_compression
// or EXT_meshopt_compression one (see gltf_write_compress.h). The buffer is split into its views,
// Draco replaces each primitive's attribute and index views by one compressed view, meshopt
// replaces eligible views by compressed payloads with a fallback buffer, and the views are joined
// again into one binary buffer.
#include "io/gltf_write_compress.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>

#include <draco/compression/decode.h>
#include <draco/compression/encode.h>
#include <meshoptimizer.h>

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

// Replaces one primitive's plain indices and attributes by a Draco compressed view.
void draco_primitive(Doc& d, json& prim, const std::string& where) {
  json& accessors = d.doc["accessors"];
  if (!prim.contains("indices") || !prim["attributes"].contains("POSITION") || prim.value("mode", 4) != 4) return;
  std::vector<std::string> names;
  bool plain_left = false;
  for (const auto& [name, a] : prim["attributes"].items()) {
    const json& acc = accessors[a.get<std::size_t>()];
    if (acc.contains("bufferView") && !acc.contains("sparse")) names.push_back(name);
    else plain_left = true;
  }
  const bool keep_order = plain_left || (prim.contains("targets") && !prim["targets"].empty());
  const auto mesh = build_draco_mesh(d, prim, names);

  draco::Encoder encoder;
  encoder.SetAttributeQuantization(draco::GeometryAttribute::POSITION, 14);
  encoder.SetAttributeQuantization(draco::GeometryAttribute::NORMAL, 10);
  encoder.SetAttributeQuantization(draco::GeometryAttribute::TEX_COORD, 12);
  encoder.SetEncodingMethod(keep_order ? draco::MESH_SEQUENTIAL_ENCODING : draco::MESH_EDGEBREAKER_ENCODING);
  draco::EncoderBuffer encoded;
  const draco::Status status = encoder.EncodeMeshToBuffer(*mesh, &encoded);
  if (!status.ok()) d.fail(where + ": Draco could not encode it (" + status.error_msg_string() + ")");

  // Decode what was written: its counts and bounds are what the accessors must say.
  draco::DecoderBuffer in;
  in.Init(encoded.data(), encoded.size());
  draco::Decoder decoder;
  auto decoded = decoder.DecodeMeshFromBuffer(&in);
  if (!decoded.ok() || !decoded.value()) d.fail(where + ": Draco cannot decode what it encoded (" + decoded.status().error_msg_string() + ")");
  const draco::Mesh& back = *decoded.value();
  if (keep_order && !keeps_vertex_order(*mesh, back))
    d.fail(where + ": Draco changed its vertex order, which its morph targets (plain accessors) depend on; "
                   "write it with --compress meshopt or without compression");

  json ext_attributes = json::object();
  for (std::size_t i = 0; i < names.size(); ++i) {
    const std::uint32_t uid = mesh->attribute(static_cast<std::int32_t>(i))->unique_id();
    if (!back.GetAttributeByUniqueId(uid)) d.fail(where + ": Draco lost attribute " + names[i]);
    ext_attributes[names[i]] = uid;
    json& acc = accessors[prim["attributes"][names[i]].get<std::size_t>()];
    acc.erase("bufferView");
    acc.erase("byteOffset");
    acc["count"] = back.num_points();
    if (names[i] == "POSITION") {
      const auto* pos = back.GetAttributeByUniqueId(uid);
      std::array<float, 3> lo{INFINITY, INFINITY, INFINITY}, hi{-INFINITY, -INFINITY, -INFINITY};
      for (std::uint32_t p = 0; p < back.num_points(); ++p) {
        float q[3];
        pos->ConvertValue<float>(pos->mapped_index(draco::PointIndex(p)), 3, q);
        for (int c = 0; c < 3; ++c) lo[std::size_t(c)] = std::min(lo[std::size_t(c)], q[c]), hi[std::size_t(c)] = std::max(hi[std::size_t(c)], q[c]);
      }
      acc["min"] = lo;
      acc["max"] = hi;
    }
  }
  json& iacc = accessors[prim["indices"].get<std::size_t>()];
  iacc.erase("bufferView");
  iacc.erase("byteOffset");
  iacc["count"] = std::size_t(back.num_faces()) * 3;
  if (back.num_points() > 65535) iacc["componentType"] = kUnsignedInt;
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

// Chooses each view meshopt can carry and encodes it; true when any was.
bool meshopt_views(Doc& d) {
  json& doc = d.doc;
  std::vector<int> readers(d.views.size(), 0);  // accessors reading a view whole; -1: other uses
  std::vector<std::size_t> reader(d.views.size(), 0);
  for (std::size_t a = 0; a < doc["accessors"].size(); ++a) {
    const json& acc = doc["accessors"][a];
    if (acc.contains("sparse")) {
      readers[acc["sparse"]["indices"]["bufferView"].get<std::size_t>()] = -1;
      readers[acc["sparse"]["values"]["bufferView"].get<std::size_t>()] = -1;
    }
    if (!acc.contains("bufferView")) continue;
    const std::size_t v = acc["bufferView"].get<std::size_t>();
    if (readers[v] >= 0) ++readers[v];
    reader[v] = a;
  }
  std::vector<bool> index_accessor(doc["accessors"].size(), false);
  if (doc.contains("meshes"))
    for (const auto& mesh : doc["meshes"])
      for (const auto& prim : mesh["primitives"])
        if (prim.contains("indices") && prim.value("mode", 4) == 4) index_accessor[prim["indices"].get<std::size_t>()] = true;
  if (doc.contains("images"))
    for (const auto& img : doc["images"])
      if (img.contains("bufferView")) readers[img["bufferView"].get<std::size_t>()] = -1;

  meshopt_encodeVertexVersion(0);
  meshopt_encodeIndexVersion(1);
  bool any = false;
  for (std::size_t v = 0; v < d.views.size(); ++v) {
    if (readers[v] != 1) continue;
    const json& acc = doc["accessors"][reader[v]];
    View& view = d.views[v];
    const std::size_t elem = d.element_size(acc), count = acc["count"].get<std::size_t>();
    const int ctype = acc["componentType"].get<int>();
    if (count == 0 || acc.value("byteOffset", std::size_t(0)) != 0 || count * elem != view.bytes.size() ||
        doc["bufferViews"][v].value("byteStride", elem) != elem)
      continue;
    if (index_accessor[reader[v]] && (ctype == kUnsignedShort || ctype == kUnsignedInt) && count % 3 == 0) {
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
    } else if (elem % 4 == 0 && elem <= 256) {
      view.payload.resize(meshopt_encodeVertexBufferBound(count, elem));
      view.payload.resize(meshopt_encodeVertexBuffer(view.payload.data(), view.payload.size(), view.bytes.data(), count, elem));
      view.mode = "ATTRIBUTES";
    } else {
      continue;
    }
    if (view.payload.empty()) d.fail("meshopt could not encode buffer view " + std::to_string(v));
    view.stride = elem;
    view.count = count;
    any = true;
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

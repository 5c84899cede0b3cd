// SPDX-License-Identifier: MIT
// glTF import: tinygltf parses the container, buffers and images; accessors are decoded here
// (strides, normalised integers, sparse) with bounds checks, and the raw JSON supplies the
// objects we carry through untouched (materials, textures, samplers, cameras, extras).
#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <filesystem>
#include <map>
#include <unordered_map>

#include <nlohmann/json.hpp>
#include <tiny_gltf.h>

#include "deepcut/core/io/gltf.h"
#include "deepcut/core/mesh_editor.h"
#include "io/gltf_common.h"

namespace deepcut {
namespace {

using nlohmann::json;
using namespace gltf_detail;

constexpr std::size_t kMaxFileBytes = std::size_t(2) << 30;     // 2 GiB
constexpr std::size_t kMaxAccessorElements = std::size_t(1) << 28;
// JSON nested deeper than this is refused before any parser sees it: tinygltf converts extras
// recursively, so a deeply nested file would otherwise overflow the stack.
constexpr int kMaxJsonDepth = 512;
// Largest image side accepted (GPUs cap textures at 16384 or 32768 pixels a side).
constexpr std::uint32_t kMaxImageSide = 32768;
// What all accessors together may decode to: this many bytes plus kDecodePerInputByte times the
// input's size (file, buffers and images). A file's own data decodes to at most 4x its size
// (normalised bytes to floats); the rest is headroom for accessors that several primitives share.
// It stops amplification: accessors without a bufferView (zero-filled, backed by no bytes) and one
// accessor reused by thousands of primitives cannot make a tiny file allocate gigabytes.
constexpr std::size_t kDecodeBaseBytes = std::size_t(64) << 20;
constexpr std::size_t kDecodePerInputByte = 32;

// ---- file system callbacks: external URIs must stay inside the model's folder ---------------

struct FsContext {
  std::filesystem::path base;  // canonical folder of the model
  bool allow_files = true;     // false when reading from memory: no file is touched at all
  std::string error;
};

bool fs_exists(const std::string& path, void* user) {
  if (!static_cast<FsContext*>(user)->allow_files) return false;
  std::error_code ec;
  return std::filesystem::exists(path, ec);
}

std::string fs_expand(const std::string& path, void*) { return path; }  // no shell expansion

bool fs_read(std::vector<unsigned char>* out, std::string* err, const std::string& path, void* user) {
  auto* ctx = static_cast<FsContext*>(user);
  if (!ctx->allow_files) {
    ctx->error = "refusing to read '" + path + "': the model was read from memory, external files are not allowed";
    if (err) *err += ctx->error;
    return false;
  }
  std::error_code ec;
  const auto canonical = std::filesystem::weakly_canonical(path, ec);
  const auto rel = canonical.lexically_relative(ctx->base);
  if (ec || rel.empty() || *rel.begin() == "..") {
    ctx->error = "refusing to read '" + path + "': it is outside the model's folder";
    if (err) *err += ctx->error;
    return false;
  }
  try {
    *out = read_file(canonical.string(), kMaxFileBytes);
  } catch (const Error& e) {
    ctx->error = e.what();
    if (err) *err += ctx->error;
    return false;
  }
  return true;
}

bool fs_write(std::string* err, const std::string&, const std::vector<unsigned char>&, void*) {
  if (err) *err += "writing is not allowed while reading";
  return false;
}

// Keeps the encoded bytes; decoding is the viewer's business. Images in a bufferView are skipped:
// tinygltf hands them over without checking the view against its buffer (a view past the end
// would be read out of bounds), and Reader::read_images copies them itself with bounds checks.
bool keep_image_bytes(tinygltf::Image* image, const int, std::string*, std::string*, int, int,
                      const unsigned char* bytes, int size, void*) {
  if (image->bufferView < 0 && size > 0) image->image.assign(bytes, bytes + size);
  image->width = image->height = -1;
  return true;
}

// ---- text helpers ------------------------------------------------------------------------------

// True when arrays/objects in the JSON text nest deeper than `limit` (strings are skipped).
bool json_nests_deeper_than(const std::string& text, int limit) {
  int depth = 0;
  bool in_string = false, escaped = false;
  for (const char c : text) {
    if (in_string) {
      if (escaped) escaped = false;
      else if (c == '\\') escaped = true;
      else if (c == '"') in_string = false;
    } else if (c == '"') {
      in_string = true;
    } else if (c == '[' || c == '{') {
      if (++depth > limit) return true;
    } else if (c == ']' || c == '}') {
      --depth;
    }
  }
  return false;
}

// "a%2Fb" -> "a/b" (RFC 3986 percent-decoding; malformed escapes are kept as they are).
std::string percent_decode(const std::string& uri) {
  auto hex = [](char c) {
    if (c >= '0' && c <= '9') return c - '0';
    if (c >= 'a' && c <= 'f') return c - 'a' + 10;
    if (c >= 'A' && c <= 'F') return c - 'A' + 10;
    return -1;
  };
  std::string out;
  for (std::size_t i = 0; i < uri.size(); ++i) {
    if (uri[i] == '%' && i + 2 < uri.size() && hex(uri[i + 1]) >= 0 && hex(uri[i + 2]) >= 0) {
      out += static_cast<char>(hex(uri[i + 1]) * 16 + hex(uri[i + 2]));
      i += 2;
    } else {
      out += uri[i];
    }
  }
  return out;
}

// True for "http://...", "file:...", "C:..." : a URI with a scheme, not a relative path.
bool has_uri_scheme(const std::string& uri) {
  const auto colon = uri.find(':');
  if (colon == std::string::npos || colon == 0 || !std::isalpha(static_cast<unsigned char>(uri[0]))) return false;
  for (std::size_t i = 1; i < colon; ++i) {
    const auto c = static_cast<unsigned char>(uri[i]);
    if (!std::isalnum(c) && c != '+' && c != '-' && c != '.') return false;
  }
  return true;
}

// Keeps messages to one readable line: control characters become spaces and any run of more
// than 100 characters without a space (a data URI quoted by tinygltf) is cut short.
std::string one_line(const std::string& text) {
  std::string out;
  std::size_t run = 0;
  for (std::size_t i = 0; i < text.size(); ++i) {
    char c = text[i];
    if (static_cast<unsigned char>(c) < 0x20 || c == 0x7F) c = ' ';
    run = c == ' ' ? 0 : run + 1;
    if (run == 61) {
      std::size_t end = i;
      while (end < text.size() && text[end] != ' ') ++end;
      if (end - i > 40) {
        out += "...(" + std::to_string(end - i + 60) + " characters)";
        i = end - 1;
        run = 0;
        continue;
      }
    }
    out += c;
  }
  return out;
}

// ---- the reader -------------------------------------------------------------------------------

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

  void parse_container();
  void check_uris() const;
  std::vector<float> read_floats(int accessor, const char* what, int* components_out = nullptr);
  std::vector<std::uint32_t> read_uints(int accessor, const char* what, int* components_out = nullptr);
  template <class T, class Convert>
  std::vector<T> decode(int accessor, const char* what, int* components_out, Convert convert);
  const unsigned char* view_bytes(int view, std::size_t offset, std::size_t stride, std::size_t elem,
                                  std::size_t count, const std::string& what);

  void read_nodes();
  void read_skins();
  void read_animations();
  void read_meshes();
  void read_images();
  void read_passthrough();
  Primitive read_primitive(const tinygltf::Primitive& p, const std::string& where, int joint_count);

  std::string path_;
  ImportOptions options_;
  const std::vector<unsigned char>* memory_ = nullptr;
  std::size_t decode_left_ = 0;  // bytes that accessors may still decode to (see kDecodeBaseBytes)
  tinygltf::Model gltf_;
  json raw_;
  Model model_;
};

void Reader::parse_container() {
  std::vector<unsigned char> file_bytes;
  if (!memory_) file_bytes = read_file(path_, kMaxFileBytes);
  const std::vector<unsigned char>& bytes = memory_ ? *memory_ : file_bytes;
  if (bytes.empty()) fail("file is empty");
  if (bytes.size() > kMaxFileBytes) fail("input is over the " + std::to_string(kMaxFileBytes >> 20) + " MiB limit");
  FsContext ctx;
  ctx.allow_files = memory_ == nullptr;
  std::error_code ec;
  if (ctx.allow_files)
    ctx.base = std::filesystem::weakly_canonical(std::filesystem::absolute(path_).parent_path(), ec);
  const std::string base_dir = ctx.base.string();

  tinygltf::TinyGLTF loader;
  loader.SetFsCallbacks(tinygltf::FsCallbacks{&fs_exists, &fs_expand, &fs_read, &fs_write, &ctx});
  loader.SetImageLoader(&keep_image_bytes, nullptr);
  std::string err, warn;
  bool ok = false;
  std::string json_text;

  const bool glb = bytes.size() >= 4 && std::memcmp(bytes.data(), "glTF", 4) == 0;
  if (glb) {
    // Check the container ourselves so a broken file gets a precise message.
    if (bytes.size() < 20) fail("truncated .glb (" + std::to_string(bytes.size()) + " bytes, header needs 20)");
    std::uint32_t header[5];
    std::memcpy(header, bytes.data(), 20);
    if (header[1] != 2) fail(".glb version " + std::to_string(header[1]) + " is not supported (need 2)");
    if (header[2] > bytes.size())
      fail("truncated .glb: header says " + std::to_string(header[2]) + " bytes, file has " + std::to_string(bytes.size()));
    if (header[4] != 0x4E4F534Au) fail(".glb first chunk is not JSON");
    if (std::size_t(header[3]) + 20 > header[2]) fail(".glb JSON chunk length runs past the end of the file");
    json_text.assign(reinterpret_cast<const char*>(bytes.data()) + 20, header[3]);
    const std::size_t bin_start = 20 + ((std::size_t(header[3]) + 3) & ~std::size_t(3));
    if (bin_start + 8 <= header[2]) {
      std::uint32_t chunk[2];
      std::memcpy(chunk, bytes.data() + bin_start, 8);
      if (bin_start + 8 + std::size_t(chunk[0]) > header[2]) fail(".glb BIN chunk length runs past the end of the file");
    }
  } else if (has_extension(path_, ".glb")) {
    fail("not a .glb file: it does not start with the magic 'glTF'");
  } else {
    json_text.assign(bytes.begin(), bytes.end());
  }
  if (json_nests_deeper_than(json_text, kMaxJsonDepth))
    fail("JSON nests arrays or objects more than " + std::to_string(kMaxJsonDepth) + " levels deep");
  try {
    raw_ = json::parse(json_text);
  } catch (const json::parse_error& e) {
    std::string msg = e.what();
    const auto pos = msg.find("parse error");
    fail("invalid JSON (" + (pos == std::string::npos ? msg : msg.substr(pos)) + ")");
  }
  if (!raw_.is_object()) fail("invalid glTF: the top level is not a JSON object");
  if (!raw_.contains("asset") || !raw_["asset"].is_object()) fail("invalid glTF: 'asset' is missing");
  const std::string version = raw_["asset"].value("version", "");
  if (version.rfind("2.", 0) != 0) fail("glTF version '" + version + "' is not supported (need 2.x)");
  for (const char* ext : {"KHR_draco_mesh_compression", "EXT_meshopt_compression"})
    if (raw_.contains("extensionsRequired") && raw_["extensionsRequired"].is_array())
      for (const auto& e : raw_["extensionsRequired"])
        if (e.is_string() && e.get<std::string>() == ext) fail(std::string("requires ") + ext + ", which is not supported");
  for (const char* key : {"accessors", "animations", "buffers", "bufferViews", "cameras", "images", "materials", "meshes",
                          "nodes", "samplers", "scenes", "skins", "textures", "extensionsUsed", "extensionsRequired"})
    if (raw_.contains(key) && !raw_[key].is_array()) fail(std::string("invalid glTF: '") + key + "' is not an array");
  check_uris();

  if (glb) {
    ok = loader.LoadBinaryFromMemory(&gltf_, &err, &warn, bytes.data(), static_cast<unsigned>(bytes.size()), base_dir);
  } else {
    ok = loader.LoadASCIIFromString(&gltf_, &err, &warn, json_text.data(), static_cast<unsigned>(json_text.size()),
                                    base_dir);
  }
  // tinygltf 2.7 reports a skin without inverseBindMatrices as an error although the spec makes
  // them optional; it still parses the skin (with -1), so that message alone is not a failure.
  std::string real_errors;
  std::size_t start = 0;
  while (start < err.size()) {
    auto end = err.find('\n', start);
    if (end == std::string::npos) end = err.size();
    const std::string line = err.substr(start, end - start);
    if (!line.empty() && line.find("'inverseBindMatrices' property is missing") == std::string::npos)
      real_errors += (real_errors.empty() ? "" : "; ") + line;
    start = end + 1;
  }
  if (!ctx.error.empty()) fail(ctx.error);
  if (!ok || !real_errors.empty()) fail(real_errors.empty() ? "tinygltf could not parse the file" : real_errors);
  std::size_t input_bytes = bytes.size();
  for (const auto& b : gltf_.buffers) input_bytes += b.data.size();
  for (const auto& i : gltf_.images) input_bytes += i.image.size();
  decode_left_ = kDecodeBaseBytes + kDecodePerInputByte * input_bytes;
}

// External URIs are checked before tinygltf resolves them: only relative paths that stay inside
// the model's folder are read (fs_read checks the resolved path again, which catches symlinks).
void Reader::check_uris() const {
  for (const char* key : {"buffers", "images"}) {
    if (!raw_.contains(key) || !raw_[key].is_array()) continue;
    const std::string kind = std::string(key) == "buffers" ? "buffer" : "image";
    for (std::size_t i = 0; i < raw_[key].size(); ++i) {
      const json& o = raw_[key][i];
      if (!o.is_object() || !o.contains("uri") || !o["uri"].is_string()) continue;
      const std::string uri = o["uri"].get<std::string>();
      if (uri.rfind("data:", 0) == 0) {
        // A base64 data URI's size is known without decoding it: say plainly when it is wrong.
        const auto comma = uri.find(',');
        if (kind != "buffer" || comma == std::string::npos || uri.rfind(";base64", comma) == std::string::npos) continue;
        std::size_t chars = 0;
        bool valid = true;
        for (std::size_t c = comma + 1; c < uri.size() && uri[c] != '='; ++c) {
          const auto ch = static_cast<unsigned char>(uri[c]);
          valid = valid && (std::isalnum(ch) || ch == '+' || ch == '/');
          ++chars;
        }
        if (!valid) fail(kind + " " + std::to_string(i) + ": its data URI is not valid base64");
        const std::size_t holds = chars * 3 / 4;
        if (o.contains("byteLength") && o["byteLength"].is_number_unsigned() && o["byteLength"].get<std::uint64_t>() > holds)
          fail(kind + " " + std::to_string(i) + " claims " + std::to_string(o["byteLength"].get<std::uint64_t>()) +
               " bytes, its data URI holds " + std::to_string(holds));
        continue;
      }
      const std::string what = kind + " " + std::to_string(i) + " URI '" + uri + "'";
      if (memory_) fail(what + " names an external file, but a model read from memory may only use data: URIs");
      const std::string decoded = percent_decode(uri);
      if (decoded.empty()) fail(what + " is empty");
      if (has_uri_scheme(decoded)) fail(what + " is not a relative file path; only files inside the model's folder are read");
      const std::filesystem::path rel(decoded);
      if (rel.is_absolute())
        fail(what + " is an absolute path, outside the model's folder (refused, not read)");
      const auto normal = rel.lexically_normal();
      if (normal.empty() || *normal.begin() == "..")
        fail(what + " points outside the model's folder (refused, not read)");
    }
  }
}

// Where `count` elements of `elem` bytes, `stride` apart, start at `offset` inside bufferView `view`;
// fails unless all of them lie inside the view and the view inside its buffer. The arithmetic
// cannot overflow, whatever the file claims.
const unsigned char* Reader::view_bytes(int view, std::size_t offset, std::size_t stride, std::size_t elem,
                                        std::size_t count, const std::string& what) {
  if (view < 0 || static_cast<std::size_t>(view) >= gltf_.bufferViews.size())
    fail(what + ": bufferView " + std::to_string(view) + " does not exist");
  const auto& bv = gltf_.bufferViews[view];
  if (bv.buffer < 0 || static_cast<std::size_t>(bv.buffer) >= gltf_.buffers.size())
    fail(what + ": buffer " + std::to_string(bv.buffer) + " does not exist");
  const auto& buf = gltf_.buffers[bv.buffer].data;
  if (bv.byteOffset > buf.size() || bv.byteLength > buf.size() - bv.byteOffset)
    fail(what + ": bufferView " + std::to_string(view) + " runs past the end of its buffer");
  if (count > 0) {
    const std::size_t size = bv.byteLength;
    const bool fits = offset <= size && elem <= size - offset &&
                      (count == 1 || stride == 0 || count - 1 <= (size - offset - elem) / stride);
    if (!fits)
      fail(what + ": " + std::to_string(count) + " elements of " + std::to_string(elem) + " bytes at offset " +
           std::to_string(offset) + " run past the end of bufferView " + std::to_string(view) + " (" +
           std::to_string(size) + " bytes)");
  }
  return buf.data() + bv.byteOffset + (count > 0 ? offset : 0);
}

template <class T, class Convert>
std::vector<T> Reader::decode(int index, const char* what_c, int* components_out, Convert convert) {
  const std::string what = std::string(what_c) + " (accessor " + std::to_string(index) + ")";
  if (index < 0 || static_cast<std::size_t>(index) >= gltf_.accessors.size())
    fail(std::string(what_c) + ": accessor " + std::to_string(index) + " does not exist");
  const auto& acc = gltf_.accessors[index];
  int comps = 0;
  switch (acc.type) {
    case TINYGLTF_TYPE_SCALAR: comps = 1; break;
    case TINYGLTF_TYPE_VEC2: comps = 2; break;
    case TINYGLTF_TYPE_VEC3: comps = 3; break;
    case TINYGLTF_TYPE_VEC4: comps = 4; break;
    case TINYGLTF_TYPE_MAT2: comps = 4; break;
    case TINYGLTF_TYPE_MAT3: comps = 9; break;
    case TINYGLTF_TYPE_MAT4: comps = 16; break;
    default: fail(what + ": unknown type");
  }
  const int csize = component_size(acc.componentType);
  if (csize == 0) fail(what + ": unknown componentType " + std::to_string(acc.componentType));
  if (acc.count > kMaxAccessorElements) fail(what + ": count " + std::to_string(acc.count) + " is implausibly large");
  if (components_out) *components_out = comps;
  const std::size_t elem = std::size_t(comps) * std::size_t(csize);

  // Every claim is checked against the bytes that back it before anything is allocated: a tiny
  // file may claim millions of elements.
  const unsigned char* base = nullptr;
  std::size_t stride = elem;
  if (acc.bufferView >= 0) {
    if (static_cast<std::size_t>(acc.bufferView) >= gltf_.bufferViews.size())
      fail(what + ": bufferView " + std::to_string(acc.bufferView) + " does not exist");
    const auto& bv = gltf_.bufferViews[acc.bufferView];
    if (bv.byteStride) stride = bv.byteStride;
    if (stride < elem) fail(what + ": byteStride " + std::to_string(stride) + " is smaller than an element");
    base = view_bytes(acc.bufferView, acc.byteOffset, stride, elem, acc.count, what);
  }
  const std::size_t decoded_bytes = acc.count * std::size_t(comps) * sizeof(T);  // <= 2^28 * 16 * 4
  if (decoded_bytes > decode_left_)
    fail(what + ": decoding " + std::to_string(acc.count) + " elements" +
         (acc.bufferView < 0 ? " (no bufferView: zeros)" : "") + " would take the model past " +
         std::to_string(kDecodeBaseBytes >> 20) + " MiB plus " + std::to_string(kDecodePerInputByte) +
         " times its input size; the file claims far more data than it holds");
  decode_left_ -= decoded_bytes;
  const auto& sp = acc.sparse;
  const std::size_t n = sp.isSparse ? static_cast<std::size_t>(std::max(sp.count, 0)) : 0;
  const unsigned char* ibase = nullptr;
  const unsigned char* vbase = nullptr;
  int isize = 0;
  if (sp.isSparse) {
    if (sp.count < 0 || n > acc.count) fail(what + ": sparse count " + std::to_string(sp.count) + " is out of range");
    isize = component_size(sp.indices.componentType);
    if (isize == 0 || sp.indices.componentType == kFloat) fail(what + ": sparse indices have a bad componentType");
    if (sp.indices.byteOffset < 0 || sp.values.byteOffset < 0) fail(what + ": sparse byteOffset is negative");
    ibase = view_bytes(sp.indices.bufferView, std::size_t(sp.indices.byteOffset), std::size_t(isize), std::size_t(isize), n,
                       what + " sparse indices");
    vbase = view_bytes(sp.values.bufferView, std::size_t(sp.values.byteOffset), elem, elem, n, what + " sparse values");
  }

  std::vector<T> out(acc.count * std::size_t(comps), T(0));
  auto load = [&](const unsigned char* from, std::size_t step, std::size_t count, auto&& dst_index) {
    for (std::size_t i = 0; i < count; ++i) {
      const unsigned char* p = from + i * step;
      const std::size_t d = dst_index(i);
      for (int c = 0; c < comps; ++c) out[d * comps + c] = convert(p + std::size_t(c) * csize, acc.componentType, acc.normalized);
    }
  };
  if (base) load(base, stride, acc.count, [](std::size_t i) { return i; });
  if (sp.isSparse) {
    std::vector<std::size_t> targets(n);
    for (std::size_t i = 0; i < n; ++i) {
      std::uint32_t idx = 0;
      if (isize == 1) idx = ibase[i];
      else if (isize == 2) { std::uint16_t v; std::memcpy(&v, ibase + 2 * i, 2); idx = v; }
      else std::memcpy(&idx, ibase + 4 * i, 4);
      if (idx >= acc.count) fail(what + ": sparse index " + std::to_string(idx) + " is out of range");
      targets[i] = idx;
    }
    load(vbase, elem, n, [&](std::size_t i) { return targets[i]; });
  }
  return out;
}

float to_float(const unsigned char* p, int type, bool normalized) {
  switch (type) {
    case kFloat: { float f; std::memcpy(&f, p, 4); return f; }
    case kByte: { const auto v = static_cast<std::int8_t>(*p); return normalized ? std::max(v / 127.0f, -1.0f) : float(v); }
    case kUnsignedByte: return normalized ? *p / 255.0f : float(*p);
    case kShort: { std::int16_t v; std::memcpy(&v, p, 2); return normalized ? std::max(v / 32767.0f, -1.0f) : float(v); }
    case kUnsignedShort: { std::uint16_t v; std::memcpy(&v, p, 2); return normalized ? v / 65535.0f : float(v); }
    case kUnsignedInt: { std::uint32_t v; std::memcpy(&v, p, 4); return normalized ? float(v / 4294967295.0) : float(v); }
    default: return 0.0f;
  }
}

std::uint32_t to_uint(const unsigned char* p, int type, bool) {
  switch (type) {
    case kUnsignedByte: return *p;
    case kUnsignedShort: { std::uint16_t v; std::memcpy(&v, p, 2); return v; }
    case kUnsignedInt: { std::uint32_t v; std::memcpy(&v, p, 4); return v; }
    case kByte: return static_cast<std::uint32_t>(std::max<int>(0, static_cast<std::int8_t>(*p)));
    case kShort: { std::int16_t v; std::memcpy(&v, p, 2); return static_cast<std::uint32_t>(std::max<int>(0, v)); }
    case kFloat: {  // past 2^32 the cast is undefined: such a value is out of every range anyway
      float f;
      std::memcpy(&f, p, 4);
      if (!(f > 0.0f)) return 0u;
      return f < 4294967296.0f ? static_cast<std::uint32_t>(f) : std::numeric_limits<std::uint32_t>::max();
    }
    default: return 0;
  }
}

std::vector<float> Reader::read_floats(int accessor, const char* what, int* components_out) {
  return decode<float>(accessor, what, components_out, &to_float);
}

std::vector<std::uint32_t> Reader::read_uints(int accessor, const char* what, int* components_out) {
  return decode<std::uint32_t>(accessor, what, components_out, &to_uint);
}

std::string dump_member(const json& o, const char* key) {
  if (!o.is_object() || !o.contains(key)) return "";
  return o[key].dump();
}

void Reader::read_nodes() {
  const json empty = json::object();
  for (std::size_t i = 0; i < gltf_.nodes.size(); ++i) {
    const auto& g = gltf_.nodes[i];
    const json& r = raw_.contains("nodes") && raw_["nodes"].is_array() && i < raw_["nodes"].size() ? raw_["nodes"][i] : empty;
    Node n;
    n.name = g.name;
    for (int c : g.children) {
      if (c < 0 || static_cast<std::size_t>(c) >= gltf_.nodes.size())
        fail("node " + std::to_string(i) + " has child " + std::to_string(c) + ", which does not exist");
      n.children.push_back(c);
    }
    if (g.matrix.size() == 16) {
      glm::mat4 m;
      for (int k = 0; k < 16; ++k) m[k / 4][k % 4] = static_cast<float>(g.matrix[k]);
      n.matrix = m;
    }
    if (g.translation.size() == 3) n.translation = glm::vec3(g.translation[0], g.translation[1], g.translation[2]);
    if (g.rotation.size() == 4)
      n.rotation = glm::quat(static_cast<float>(g.rotation[3]), static_cast<float>(g.rotation[0]),
                             static_cast<float>(g.rotation[1]), static_cast<float>(g.rotation[2]));
    if (g.scale.size() == 3) n.scale = glm::vec3(g.scale[0], g.scale[1], g.scale[2]);
    bool finite = true;
    if (n.matrix)
      for (int k = 0; k < 16; ++k) finite = finite && std::isfinite((*n.matrix)[k / 4][k % 4]);
    for (int k = 0; k < 3; ++k) finite = finite && std::isfinite(n.translation[k]) && std::isfinite(n.scale[k]);
    for (int k = 0; k < 4; ++k) finite = finite && std::isfinite(n.rotation[k]);
    if (!finite) fail("node " + std::to_string(i) + ": its transform is not finite (a value overflows a 32-bit float)");
    auto check = [&](int idx, std::size_t size, const char* kind) {
      if (idx >= 0 && static_cast<std::size_t>(idx) >= size)
        fail("node " + std::to_string(i) + " refers to " + kind + " " + std::to_string(idx) + ", which does not exist");
      return idx;
    };
    n.mesh = check(g.mesh, gltf_.meshes.size(), "mesh");
    n.skin = check(g.skin, gltf_.skins.size(), "skin");
    n.camera = check(g.camera, gltf_.cameras.size(), "camera");
    n.extras_json = dump_member(r, "extras");
    n.extensions_json = dump_member(r, "extensions");
    if (!g.weights.empty()) note("node '" + g.name + "': morph target weights dropped (morph targets are not supported)");
    model_.nodes.push_back(std::move(n));
  }
  // Cycles or a node with two parents would make the hierarchy ill-defined.
  std::vector<int> parent(model_.nodes.size(), -1);
  for (std::size_t i = 0; i < model_.nodes.size(); ++i)
    for (int c : model_.nodes[i].children) {
      if (parent[c] >= 0 || c == static_cast<int>(i)) fail("node " + std::to_string(c) + " has more than one parent");
      parent[c] = static_cast<int>(i);
    }
  for (std::size_t i = 0; i < parent.size(); ++i) {
    std::size_t steps = 0;
    for (int x = parent[i]; x >= 0; x = parent[x])
      if (++steps > parent.size()) fail("the node hierarchy has a cycle through node " + std::to_string(i));
  }
  for (const auto& s : gltf_.scenes) {
    std::vector<int> roots;
    for (int n : s.nodes) {
      if (n < 0 || static_cast<std::size_t>(n) >= gltf_.nodes.size()) fail("a scene refers to node " + std::to_string(n) + ", which does not exist");
      roots.push_back(n);
    }
    model_.scenes.push_back(std::move(roots));
  }
  model_.default_scene = gltf_.defaultScene >= 0 ? gltf_.defaultScene : 0;
  if (model_.scenes.empty()) {
    model_.scenes.push_back(model_.root_nodes());
    model_.default_scene = 0;
  }
}

void Reader::read_skins() {
  for (std::size_t i = 0; i < gltf_.skins.size(); ++i) {
    const auto& g = gltf_.skins[i];
    Skin s;
    s.name = g.name;
    for (int j : g.joints) {
      if (j < 0 || static_cast<std::size_t>(j) >= model_.nodes.size())
        fail("skin " + std::to_string(i) + " names joint node " + std::to_string(j) + ", which does not exist");
      s.joints.push_back(j);
    }
    if (s.joints.empty()) fail("skin " + std::to_string(i) + " has no joints");
    if (g.skeleton >= 0 && static_cast<std::size_t>(g.skeleton) < model_.nodes.size()) s.skeleton = g.skeleton;
    if (g.inverseBindMatrices >= 0) {
      int comps = 0;
      const auto m = read_floats(g.inverseBindMatrices, "skin inverseBindMatrices", &comps);
      if (comps != 16) fail("skin " + std::to_string(i) + ": inverseBindMatrices are not MAT4");
      if (m.size() / 16 < s.joints.size()) fail("skin " + std::to_string(i) + ": fewer inverseBindMatrices than joints");
      for (std::size_t j = 0; j < s.joints.size(); ++j) {
        glm::mat4 mat;
        for (int k = 0; k < 16; ++k) mat[k / 4][k % 4] = m[16 * j + static_cast<std::size_t>(k)];
        for (int k = 0; k < 16; ++k)
          if (!std::isfinite(mat[k / 4][k % 4]))
            fail("skin " + std::to_string(i) + ": inverse bind matrix " + std::to_string(j) + " is not finite (NaN or Inf)");
        s.inverse_bind_matrices.push_back(mat);
      }
    } else {
      s.had_inverse_bind_matrices = false;
      s.inverse_bind_matrices.assign(s.joints.size(), glm::mat4(1.0f));
      note("skin " + std::to_string(i) + " has no inverseBindMatrices: identity matrices used (written explicitly on export)");
    }
    model_.skins.push_back(std::move(s));
  }
}

void Reader::read_animations() {
  for (std::size_t a = 0; a < gltf_.animations.size(); ++a) {
    const auto& g = gltf_.animations[a];
    Animation anim;
    anim.name = g.name;
    std::vector<int> sampler_map(g.samplers.size(), -1);
    for (std::size_t c = 0; c < g.channels.size(); ++c) {
      const auto& ch = g.channels[c];
      if (ch.sampler < 0 || static_cast<std::size_t>(ch.sampler) >= g.samplers.size())
        fail("animation " + std::to_string(a) + " channel " + std::to_string(c) + " refers to a missing sampler");
      if (ch.target_node < 0) continue;  // targets defined by extensions are not animated here
      if (static_cast<std::size_t>(ch.target_node) >= model_.nodes.size())
        fail("animation " + std::to_string(a) + " channel " + std::to_string(c) + " targets a missing node");
      AnimationChannel out;
      out.node = ch.target_node;
      if (ch.target_path == "translation") out.path = AnimationPath::Translation;
      else if (ch.target_path == "rotation") out.path = AnimationPath::Rotation;
      else if (ch.target_path == "scale") out.path = AnimationPath::Scale;
      else if (ch.target_path == "weights") {
        note("animation '" + g.name + "': morph weight channel dropped (morph targets are not supported)");
        continue;
      } else fail("animation " + std::to_string(a) + " channel " + std::to_string(c) + ": unknown path '" + ch.target_path + "'");
      if (sampler_map[ch.sampler] < 0) {
        const auto& gs = g.samplers[ch.sampler];
        AnimationSampler s;
        int in_comps = 0, out_comps = 0;
        s.input = read_floats(gs.input, "animation sampler input", &in_comps);
        s.output = read_floats(gs.output, "animation sampler output", &out_comps);
        if (in_comps != 1) fail("animation " + std::to_string(a) + ": sampler input is not SCALAR");
        for (std::size_t k = 0; k < s.input.size(); ++k) {
          if (!std::isfinite(s.input[k])) fail("animation " + std::to_string(a) + ": key time is not finite");
          if (k && s.input[k] < s.input[k - 1]) fail("animation " + std::to_string(a) + ": key times are not increasing");
        }
        s.components = out_comps;
        if (gs.interpolation == "STEP") s.interpolation = Interpolation::Step;
        else if (gs.interpolation == "CUBICSPLINE") s.interpolation = Interpolation::CubicSpline;
        else s.interpolation = Interpolation::Linear;
        const std::size_t per_key = s.interpolation == Interpolation::CubicSpline ? 3 : 1;
        if (s.output.size() != s.input.size() * per_key * std::size_t(out_comps))
          fail("animation " + std::to_string(a) + ": sampler output count does not match its input count");
        for (const float v : s.output)
          if (!std::isfinite(v)) fail("animation " + std::to_string(a) + ": a sampler output value is not finite (NaN or Inf)");
        sampler_map[ch.sampler] = static_cast<int>(anim.samplers.size());
        anim.samplers.push_back(std::move(s));
      }
      out.sampler = sampler_map[ch.sampler];
      const int need = out.path == AnimationPath::Rotation ? 4 : 3;
      if (anim.samplers[out.sampler].components != need)
        fail("animation " + std::to_string(a) + " channel " + std::to_string(c) + ": output has the wrong type for " + ch.target_path);
      if (out.path == AnimationPath::Rotation) {
        // Rotations must be unit quaternions (glTF; the validator checks it): normalise them, and
        // make a zero one the identity. For cubic splines only the values, not the tangents.
        auto& smp = anim.samplers[out.sampler];
        const std::size_t per_key = smp.interpolation == Interpolation::CubicSpline ? 3 : 1;
        // Float noise (SimpleSkin's 0.707s are 1.5e-4 short) is fixed silently, larger errors noted.
        std::size_t fixed = 0;
        for (std::size_t k = 0; k < smp.input.size(); ++k) {
          float* q = &smp.output[4 * (k * per_key + (per_key == 3 ? 1 : 0))];
          const double len = std::sqrt(double(q[0]) * q[0] + double(q[1]) * q[1] + double(q[2]) * q[2] + double(q[3]) * q[3]);
          if (std::abs(len - 1.0) <= 1e-6) continue;
          fixed += std::abs(len - 1.0) > 1e-3;
          if (len < 1e-12 || !std::isfinite(len)) {
            q[0] = q[1] = q[2] = 0.0f;
            q[3] = 1.0f;
          } else {
            for (int i = 0; i < 4; ++i) q[i] = static_cast<float>(q[i] / len);
          }
        }
        if (fixed)
          note("animation " + std::to_string(a) + " channel " + std::to_string(c) + ": " + std::to_string(fixed) +
               " rotations were not unit quaternions (normalised)");
      }
      anim.channels.push_back(out);
    }
    model_.animations.push_back(std::move(anim));
  }
}

Primitive Reader::read_primitive(const tinygltf::Primitive& p, const std::string& where, int joint_count) {
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
  auto pos_it = p.attributes.find("POSITION");
  if (pos_it == p.attributes.end()) fail(where + " has no POSITION attribute");
  int comps = 0;
  const auto pos = read_floats(pos_it->second, "POSITION", &comps);
  if (comps != 3) fail(where + ": POSITION is not VEC3");
  const std::size_t nv = pos.size() / 3;
  for (std::size_t i = 0; i < pos.size(); ++i)
    if (!std::isfinite(pos[i])) fail(where + ": POSITION " + std::to_string(i / 3) + " is not finite (NaN or Inf)");
  out.gltf_vertices = nv;

  // Triangles as glTF vertex indices.
  std::vector<std::uint32_t> idx;
  if (p.indices >= 0) {
    int ic = 0;
    idx = read_uints(p.indices, "indices", &ic);
    if (ic != 1) fail(where + ": indices are not SCALAR");
    if (gltf_.accessors[p.indices].componentType == kFloat) fail(where + ": indices must be integers");
    for (std::size_t i = 0; i < idx.size(); ++i)
      if (idx[i] >= nv)
        fail(where + ": index " + std::to_string(idx[i]) + " (position " + std::to_string(i) + ") is past the " +
             std::to_string(nv) + " vertices");
  } else {
    idx.resize(nv);
    for (std::size_t i = 0; i < nv; ++i) idx[i] = static_cast<std::uint32_t>(i);
  }
  std::vector<std::uint32_t> tris;
  if (p.mode == TINYGLTF_MODE_TRIANGLE_STRIP) {
    for (std::size_t i = 2; i < idx.size(); ++i) {
      if (i % 2 == 0) tris.insert(tris.end(), {idx[i - 2], idx[i - 1], idx[i]});
      else tris.insert(tris.end(), {idx[i - 1], idx[i - 2], idx[i]});
    }
    note(where + ": triangle strip converted to triangles");
  } else if (p.mode == TINYGLTF_MODE_TRIANGLE_FAN) {
    for (std::size_t i = 2; i < idx.size(); ++i) tris.insert(tris.end(), {idx[0], idx[i - 1], idx[i]});
    note(where + ": triangle fan converted to triangles");
  } else {
    if (idx.size() % 3 != 0) fail(where + ": index count " + std::to_string(idx.size()) + " is not a multiple of 3");
    tris = std::move(idx);
  }

  // Vertex attributes: skin influences.
  struct SkinSetData {
    std::vector<std::uint32_t> joints;
    std::vector<float> weights;
  };
  std::vector<SkinSetData> sets;
  for (int s = 0; s < 2; ++s) {
    auto j = p.attributes.find("JOINTS_" + std::to_string(s));
    auto w = p.attributes.find("WEIGHTS_" + std::to_string(s));
    if (j == p.attributes.end() || w == p.attributes.end()) break;
    SkinSetData d;
    int jc = 0, wc = 0;
    d.joints = read_uints(j->second, "JOINTS", &jc);
    d.weights = read_floats(w->second, "WEIGHTS", &wc);
    if (jc != 4 || wc != 4 || d.joints.size() != 4 * nv || d.weights.size() != 4 * nv)
      fail(where + ": JOINTS_" + std::to_string(s) + "/WEIGHTS_" + std::to_string(s) + " must be VEC4 with one per vertex");
    sets.push_back(std::move(d));
  }
  const int slots = 4 * static_cast<int>(sets.size());
  std::size_t renormalised = 0, out_of_range = 0, zero = 0, bad_weights = 0;
  std::vector<glm::u16vec4> joints(sets.size() * nv);
  std::vector<glm::vec4> weights(sets.size() * nv);
  for (std::size_t v = 0; v < nv && slots > 0; ++v) {
    std::uint16_t jj[8] = {};
    float ww[8] = {};
    double sum = 0.0;
    for (int k = 0; k < slots; ++k) {
      const auto& d = sets[std::size_t(k / 4)];
      std::uint32_t joint = d.joints[4 * v + std::size_t(k % 4)];
      float weight = d.weights[4 * v + std::size_t(k % 4)];
      if (!std::isfinite(weight) || weight < 0.0f) {
        ++bad_weights;
        weight = 0.0f;
      }
      if (joint_count >= 0 && joint >= static_cast<std::uint32_t>(joint_count)) {
        // Dropped, and the slot points at joint 0: a vertex left with no weight is bound to its
        // first slot's joint, which must exist.
        out_of_range += weight > 0.0f;
        weight = 0.0f;
        joint = 0;
      }
      if (joint > 65535u) joint = 0;
      jj[k] = static_cast<std::uint16_t>(joint);
      ww[k] = weight;
      sum += weight;
    }
    if (std::abs(sum - 1.0) > 1e-3) ++renormalised;
    if (!normalize_influences(jj, ww, slots)) ++zero;
    for (std::size_t s = 0; s < sets.size(); ++s) {
      joints[s * nv + v] = glm::u16vec4(jj[4 * s], jj[4 * s + 1], jj[4 * s + 2], jj[4 * s + 3]);
      weights[s * nv + v] = glm::vec4(ww[4 * s], ww[4 * s + 1], ww[4 * s + 2], ww[4 * s + 3]);
    }
  }
  if (bad_weights) note(where + ": " + std::to_string(bad_weights) + " weights were negative or NaN (set to 0)");
  if (renormalised) note(where + ": " + std::to_string(renormalised) + " vertices had weights not summing to 1 (normalised)");
  if (out_of_range) note(where + ": " + std::to_string(out_of_range) + " influences named a joint past the skin (dropped)");
  if (zero) note(where + ": " + std::to_string(zero) + " vertices had no weight (bound to their first joint)");

  // Corner attributes.
  struct CornerSource {
    std::string name;
    int comps;  // stored components (2, 3 or 4)
    std::vector<float> data;
    int data_comps;
  };
  std::vector<CornerSource> corner_sources;
  for (const auto& [name, accessor] : p.attributes) {
    if (name == "POSITION" || name.rfind("JOINTS_", 0) == 0 || name.rfind("WEIGHTS_", 0) == 0) {
      if ((name.rfind("JOINTS_", 0) == 0 || name.rfind("WEIGHTS_", 0) == 0) && name.back() > '1')
        note(where + ": " + name + " dropped (at most 8 influences are kept)");
      continue;
    }
    CornerSource cs;
    if (name == "NORMAL") { cs.name = attr::kNormal; cs.comps = 3; }
    else if (name == "TANGENT") { cs.name = attr::kTangent; cs.comps = 4; }
    else if (name == "COLOR_0") { cs.name = attr::kColor0; cs.comps = 4; }
    else if (name.rfind("TEXCOORD_", 0) == 0) {
      const std::string set = name.substr(9);
      if (set.empty() || set.size() > 2 || !std::all_of(set.begin(), set.end(), [](unsigned char c) { return std::isdigit(c); })) {
        note(where + ": attribute " + name + " dropped (not a valid glTF attribute name)");
        continue;
      }
      cs.name = attr::uv_name(std::stoi(set));
      cs.comps = 2;
    }
    else {
      note(where + ": attribute " + name + " dropped (not supported)");
      continue;
    }
    cs.data = read_floats(accessor, name.c_str(), &cs.data_comps);
    if (cs.data.size() / std::size_t(std::max(cs.data_comps, 1)) != nv) fail(where + ": " + name + " count differs from POSITION count");
    const bool ok = cs.data_comps == cs.comps || (name == "COLOR_0" && cs.data_comps == 3);
    if (!ok) fail(where + ": " + name + " has " + std::to_string(cs.data_comps) + " components");
    corner_sources.push_back(std::move(cs));
  }
  if (!p.targets.empty()) note(where + ": " + std::to_string(p.targets.size()) + " morph targets dropped (not supported)");

  // Weld: one topological vertex per distinct (position, skin); numbered by first use.
  SurfaceMesh& mesh = out.mesh;
  mesh.reserve(nv, tris.size() / 3);
  struct Key {
    float p[3];
    std::uint16_t j[8];
    float w[8];
  };
  auto make_key = [&](std::uint32_t v) {
    Key k{};
    for (int c = 0; c < 3; ++c) k.p[c] = pos[3 * v + std::size_t(c)] + 0.0f;  // -0 == +0
    for (std::size_t s = 0; s < sets.size(); ++s)
      for (int c = 0; c < 4; ++c) {
        k.j[4 * s + std::size_t(c)] = joints[s * nv + v][c];
        k.w[4 * s + std::size_t(c)] = weights[s * nv + v][c];
      }
    return k;
  };
  auto key_hash = [](const Key& k) {
    std::size_t h = 1469598103934665603ull;
    const auto* b = reinterpret_cast<const unsigned char*>(&k);
    for (std::size_t i = 0; i < sizeof(Key); ++i) h = (h ^ b[i]) * 1099511628211ull;
    return h;
  };
  std::unordered_multimap<std::size_t, std::uint32_t> seen;  // hash -> welded vertex
  std::vector<Key> welded_keys;
  std::vector<std::uint32_t> gltf_to_welded(nv, kInvalidIndex);
  std::unordered_map<std::size_t, std::uint32_t> position_seen;  // position-only hash
  std::size_t kept_apart = 0;
  auto weld_vertex = [&](std::uint32_t v) {
    if (gltf_to_welded[v] != kInvalidIndex) return gltf_to_welded[v];
    const Key k = make_key(v);
    std::uint32_t id = kInvalidIndex;
    if (options_.weld) {
      const auto h = key_hash(k);
      auto range = seen.equal_range(h);
      for (auto it = range.first; it != range.second && id == kInvalidIndex; ++it)
        if (std::memcmp(&welded_keys[it->second], &k, sizeof(Key)) == 0) id = it->second;
      if (id == kInvalidIndex) {
        id = static_cast<std::uint32_t>(welded_keys.size());
        seen.emplace(h, id);
        Key pk{};
        std::memcpy(pk.p, k.p, sizeof(k.p));
        if (!position_seen.emplace(key_hash(pk), id).second) ++kept_apart;
      }
    } else {
      id = static_cast<std::uint32_t>(welded_keys.size());
    }
    if (id == welded_keys.size()) {
      welded_keys.push_back(k);
      mesh.add_vertex(glm::vec3(k.p[0], k.p[1], k.p[2]));
    }
    gltf_to_welded[v] = id;
    return id;
  };
  std::vector<std::uint32_t> corner_gltf(tris.size());
  for (std::size_t i = 0; i < tris.size(); i += 3) {
    const auto a = weld_vertex(tris[i]), b = weld_vertex(tris[i + 1]), c = weld_vertex(tris[i + 2]);
    mesh.add_face(VertexId(a), VertexId(b), VertexId(c));
    corner_gltf[i] = tris[i];
    corner_gltf[i + 1] = tris[i + 1];
    corner_gltf[i + 2] = tris[i + 2];
  }
  std::size_t referenced = 0;
  for (auto w : gltf_to_welded) referenced += w != kInvalidIndex;
  out.welded_merged = referenced - mesh.vertex_count();
  if (kept_apart)
    note(where + ": " + std::to_string(kept_apart) + " vertices share a position with different skin weights (kept apart)");
  if (referenced < nv) note(where + ": " + std::to_string(nv - referenced) + " unreferenced vertices dropped");

  // Skin attributes per welded vertex.
  if (!sets.empty()) {
    const char* jn[2] = {attr::kJoints0, attr::kJoints1};
    const char* wn[2] = {attr::kWeights0, attr::kWeights1};
    for (std::size_t s = 0; s < sets.size(); ++s) {
      auto& ja = mesh.vertex_attrs().add<glm::u16vec4>(jn[s]);
      auto& wa = mesh.vertex_attrs().add<glm::vec4>(wn[s]);
      for (std::uint32_t v = 0; v < nv; ++v) {
        const auto w = gltf_to_welded[v];
        if (w == kInvalidIndex) continue;
        ja[w] = joints[s * nv + v];
        wa[w] = weights[s * nv + v];
      }
    }
  }
  // Corner attributes from the glTF vertex of each corner.
  for (const auto& cs : corner_sources) {
    const std::size_t nc = corner_gltf.size();
    if (cs.comps == 2) {
      auto& a = mesh.corner_attrs().add<glm::vec2>(cs.name);
      for (std::size_t c = 0; c < nc; ++c) a[c] = glm::vec2(cs.data[2 * corner_gltf[c]], cs.data[2 * corner_gltf[c] + 1]);
    } else if (cs.comps == 3) {
      auto& a = mesh.corner_attrs().add<glm::vec3>(cs.name);
      for (std::size_t c = 0; c < nc; ++c) {
        const float* d = &cs.data[3 * corner_gltf[c]];
        a[c] = glm::vec3(d[0], d[1], d[2]);
      }
    } else {
      auto& a = mesh.corner_attrs().add<glm::vec4>(cs.name, glm::vec4(1.0f));
      for (std::size_t c = 0; c < nc; ++c) {
        const float* d = &cs.data[std::size_t(cs.data_comps) * corner_gltf[c]];
        a[c] = glm::vec4(d[0], d[1], d[2], cs.data_comps == 4 ? d[3] : 1.0f);
      }
    }
  }
  return out;
}

void Reader::read_meshes() {
  // The skin a mesh is drawn with decides the valid joint range of its influences.
  std::vector<int> mesh_joints(gltf_.meshes.size(), -1);
  for (const auto& n : model_.nodes)
    if (n.mesh >= 0 && n.skin >= 0) mesh_joints[n.mesh] = static_cast<int>(model_.skins[n.skin].joints.size());
  for (std::size_t m = 0; m < gltf_.meshes.size(); ++m) {
    const auto& g = gltf_.meshes[m];
    Mesh mesh;
    mesh.name = g.name;
    const json& r = raw_.contains("meshes") && m < raw_["meshes"].size() ? raw_["meshes"][m] : json::object();
    mesh.extras_json = dump_member(r, "extras");
    for (std::size_t p = 0; p < g.primitives.size(); ++p) {
      const std::string where = "mesh " + std::to_string(m) + (g.name.empty() ? "" : " '" + g.name + "'") + " primitive " +
                                std::to_string(p);
      Primitive prim = read_primitive(g.primitives[p], where, mesh_joints[m]);
      if (r.contains("primitives") && p < r["primitives"].size()) prim.extras_json = dump_member(r["primitives"][p], "extras");
      mesh.primitives.push_back(std::move(prim));
    }
    model_.meshes.push_back(std::move(mesh));
  }
}

std::string sniff_mime(const std::vector<unsigned char>& d) {
  if (d.size() >= 8 && d[0] == 0x89 && d[1] == 'P' && d[2] == 'N' && d[3] == 'G') return "image/png";
  if (d.size() >= 3 && d[0] == 0xFF && d[1] == 0xD8 && d[2] == 0xFF) return "image/jpeg";
  if (d.size() >= 12 && std::memcmp(d.data(), "RIFF", 4) == 0 && std::memcmp(d.data() + 8, "WEBP", 4) == 0) return "image/webp";
  if (d.size() >= 4 && std::memcmp(d.data(), "\xABKTX", 4) == 0) return "image/ktx2";
  return "";
}

// Width and height that a PNG or JPEG header claims ({0, 0} when unknown). Reads headers only.
std::pair<std::uint32_t, std::uint32_t> image_dimensions(const std::vector<unsigned char>& d) {
  auto be16 = [&](std::size_t at) { return std::uint32_t(d[at]) << 8 | d[at + 1]; };
  auto be32 = [&](std::size_t at) { return be16(at) << 16 | be16(at + 2); };
  if (d.size() >= 24 && d[0] == 0x89 && d[1] == 'P' && std::memcmp(d.data() + 12, "IHDR", 4) == 0) return {be32(16), be32(20)};
  if (d.size() >= 4 && d[0] == 0xFF && d[1] == 0xD8) {
    std::size_t at = 2;
    while (at + 9 < d.size() && d[at] == 0xFF) {
      const unsigned char marker = d[at + 1];
      const bool sof = marker >= 0xC0 && marker <= 0xCF && marker != 0xC4 && marker != 0xC8 && marker != 0xCC;
      if (sof) return {be16(at + 7), be16(at + 5)};
      at += 2 + be16(at + 2);
    }
  }
  return {0, 0};
}

void Reader::read_images() {
  for (std::size_t i = 0; i < gltf_.images.size(); ++i) {
    const auto& g = gltf_.images[i];
    Image img;
    img.name = g.name;
    if (g.bufferView >= 0) {
      const auto& bv = gltf_.bufferViews.at(g.bufferView);
      const unsigned char* base = view_bytes(g.bufferView, 0, 1, 1, bv.byteLength, "image " + std::to_string(i));
      img.data.assign(base, base + bv.byteLength);
    } else {
      img.data = g.image;
    }
    // Images are carried through undecoded, but whoever displays the model will decode them: a
    // header claiming more than any GPU texture can hold is a decompression bomb, not a texture.
    const auto [width, height] = image_dimensions(img.data);
    if (width > kMaxImageSide || height > kMaxImageSide)
      fail("image " + std::to_string(i) + " claims " + std::to_string(width) + " x " + std::to_string(height) +
           " pixels, over the " + std::to_string(kMaxImageSide) + "-pixel limit per side");
    img.mime_type = g.mimeType.empty() ? sniff_mime(img.data) : g.mimeType;
    if (img.mime_type.empty()) img.mime_type = "image/png";
    model_.images.push_back(std::move(img));
  }
}

void Reader::read_passthrough() {
  auto take = [&](const char* key, std::vector<PassthroughObject>& out) {
    if (!raw_.contains(key) || !raw_[key].is_array()) return;
    for (const auto& o : raw_[key]) {
      if (!o.is_object()) fail(std::string("'") + key + "' holds something that is not an object");
      out.push_back({o.value("name", ""), o.dump()});
    }
  };
  take("materials", model_.materials);
  take("textures", model_.textures);
  take("samplers", model_.samplers);
  take("cameras", model_.cameras);
  for (const auto& t : raw_.value("textures", json::array())) {
    const int src = t.value("source", -1);
    if (src >= 0 && static_cast<std::size_t>(src) >= gltf_.images.size())
      fail("a texture refers to image " + std::to_string(src) + ", which does not exist");
    const int smp = t.value("sampler", -1);
    if (smp >= 0 && static_cast<std::size_t>(smp) >= model_.samplers.size())
      fail("a texture refers to sampler " + std::to_string(smp) + ", which does not exist");
  }
  for (const char* key : {"extensionsUsed", "extensionsRequired"}) {
    if (!raw_.contains(key) || !raw_[key].is_array()) continue;
    auto& out = std::string(key) == "extensionsUsed" ? model_.extensions_used : model_.extensions_required;
    for (const auto& e : raw_[key])
      if (e.is_string()) out.push_back(e.get<std::string>());
  }
  model_.extras_json = dump_member(raw_, "extras");
  model_.asset_copyright = raw_["asset"].value("copyright", "");
}

Model Reader::read() {
  parse_container();
  read_nodes();
  read_skins();
  read_animations();
  read_images();
  read_passthrough();
  read_meshes();
  return std::move(model_);
}

}  // namespace

Model read_gltf_memory(const std::vector<unsigned char>& bytes, const std::string& name, const ImportOptions& options) {
  try {
    return Reader(name, options, &bytes).read();
  } catch (const Error&) {
    throw;
  } catch (const std::bad_alloc&) {
    throw Error(ErrorCode::InvalidInput, name + ": out of memory while reading (the file claims too much data)");
  } catch (const std::exception& e) {
    throw Error(ErrorCode::InvalidInput, name + ": " + one_line(e.what()));
  }
}

Model read_gltf(const std::string& path, const ImportOptions& options) {
  try {
    return Reader(path, options).read();
  } catch (const Error&) {
    throw;
  } catch (const std::bad_alloc&) {
    throw Error(ErrorCode::InvalidInput, path + ": out of memory while reading (the file claims too much data)");
  } catch (const std::exception& e) {
    throw Error(ErrorCode::InvalidInput, path + ": " + one_line(e.what()));
  }
}

}  // namespace deepcut

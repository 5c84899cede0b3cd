// SPDX-License-Identifier: MIT
// glTF import: the sandbox (limits, file-system callbacks), the container and the accessors
// (strides, normalised integers, sparse) with bounds checks; the raw JSON supplies the objects we
// carry through untouched (materials, textures, samplers, cameras, extras). The sections are read
// in gltf_read_scene.cpp and gltf_read_mesh.cpp.
#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <filesystem>
#include <type_traits>

#include "deepcut/core/parallel.h"

#include "io/gltf_common.h"
#include "io/gltf_reader.h"
#include "uninit_vector.h"

namespace deepcut::gltf_detail {
namespace {

using nlohmann::json;

constexpr std::size_t kMaxFileBytes = std::size_t(2) << 30;     // 2 GiB
constexpr std::size_t kMaxAccessorElements = std::size_t(1) << 28;
// JSON nested deeper than this is refused before any parser sees it: tinygltf converts extras
// recursively, so a deeply nested file would otherwise overflow the stack.
constexpr int kMaxJsonDepth = 512;
// What all accessors together may decode to: this many bytes plus kDecodePerInputByte times the
// input's size (file, buffers and images). A file's own data decodes to at most 4x its size
// (normalised bytes to floats); the rest is headroom for accessors that several primitives share.
// It stops amplification: accessors without a bufferView (zero-filled, backed by no bytes) and one
// accessor reused by thousands of primitives cannot make a tiny file allocate gigabytes.
constexpr std::size_t kDecodeBaseBytes = std::size_t(64) << 20;
constexpr std::size_t kDecodePerInputByte = 32;
// Elements per parallel chunk when decoding an accessor.
constexpr std::size_t kDecodeGrain = 32768;

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

}  // namespace

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

std::string dump_member(const json& o, const char* key) {
  if (!o.is_object() || !o.contains(key)) return "";
  return o[key].dump();
}

// ---- the reader: container and accessors -----------------------------------------------------

// The .glb's BIN chunk, when tinygltf 2.7 would accept the container as it is (JSON chunk
// ending on a 4-byte boundary, a BIN chunk of at least 4 bytes, a multiple of 4, inside the file,
// of type BIN); {nullptr, 0} otherwise. Only then is tinygltf given a stand-in for it.
ByteSpan glb_bin_chunk(const unsigned char* bytes, std::size_t size) {
  std::uint32_t header[5];
  std::memcpy(header, bytes, 20);
  const std::size_t json_end = 20 + std::size_t(header[3]), length = std::min<std::size_t>(header[2], size);
  if (json_end % 4 != 0 || json_end + 12 > length) return {nullptr, 0};
  std::uint32_t chunk[2];
  std::memcpy(chunk, bytes + json_end, 8);
  if (chunk[0] < 4 || chunk[0] % 4 != 0 || json_end + chunk[0] > length || chunk[1] != 0x004E4942u) return {nullptr, 0};
  return {bytes + json_end + 8, chunk[0]};
}

// The buffers tinygltf reads from the BIN chunk (no URI) in `doc`, the document it is given, when
// each declares a plain byteLength that fits in `bin_size` bytes; empty otherwise (tinygltf then
// reads the chunk itself and reports what is wrong in its words).
std::vector<std::size_t> buffers_in_bin(const json& doc, std::size_t bin_size) {
  std::vector<std::size_t> out;
  if (!doc.contains("buffers") || !doc["buffers"].is_array()) return out;
  const json& buffers = doc["buffers"];
  for (std::size_t b = 0; b < buffers.size(); ++b) {
    const json& o = buffers[b];
    if (!o.is_object()) return {};
    if (o.contains("uri")) {
      if (!o["uri"].is_string() || o["uri"].get_ref<const std::string&>().empty()) return {};
      continue;
    }
    if (!o.contains("byteLength") || !o["byteLength"].is_number_unsigned() || o["byteLength"].get<std::uint64_t>() > bin_size)
      return {};
    out.push_back(b);
  }
  return out;
}

void Reader::parse_container() {
  if (!memory_) file_.open(path_, kMaxFileBytes);
  const unsigned char* bytes = memory_ ? memory_->data() : file_.data();
  const std::size_t size = memory_ ? memory_->size() : file_.size();
  if (size == 0) fail("file is empty");
  if (size > kMaxFileBytes) fail("input is over the " + std::to_string(kMaxFileBytes >> 20) + " MiB limit");
  const bool glb = size >= 4 && std::memcmp(bytes, "glTF", 4) == 0;
  if (!glb && has_extension(path_, ".glb")) fail("not a .glb file: it does not start with the magic 'glTF'");
  std::string json_text =
      glb ? glb_json_chunk(bytes, size) : std::string(reinterpret_cast<const char*>(bytes), size);
  parse_json(json_text);
  load_tinygltf(bytes, size, glb, std::move(json_text));
  std::size_t input_bytes = size;
  for (std::size_t b = 0; b < gltf_.buffers.size(); ++b) input_bytes += buffer_bytes(b).size;
  for (const auto& i : gltf_.images) input_bytes += i.image.size();
  decode_left_ = kDecodeBaseBytes + kDecodePerInputByte * input_bytes;
}

// The JSON chunk of the .glb `bytes`, its container checked here so a broken file gets a precise
// message.
std::string Reader::glb_json_chunk(const unsigned char* bytes, std::size_t size) const {
  if (size < 20) fail("truncated .glb (" + std::to_string(size) + " bytes, header needs 20)");
  std::uint32_t header[5];
  std::memcpy(header, bytes, 20);
  if (header[1] != 2) fail(".glb version " + std::to_string(header[1]) + " is not supported (need 2)");
  if (header[2] > size)
    fail("truncated .glb: header says " + std::to_string(header[2]) + " bytes, file has " +
         std::to_string(size));
  if (header[4] != 0x4E4F534Au) fail(".glb first chunk is not JSON");
  if (std::size_t(header[3]) + 20 > header[2]) fail(".glb JSON chunk length runs past the end of the file");
  const std::size_t bin_start = 20 + ((std::size_t(header[3]) + 3) & ~std::size_t(3));
  if (bin_start + 8 <= header[2]) {
    std::uint32_t chunk[2];
    std::memcpy(chunk, bytes + bin_start, 8);
    if (bin_start + 8 + std::size_t(chunk[0]) > header[2])
      fail(".glb BIN chunk length runs past the end of the file");
  }
  return std::string(reinterpret_cast<const char*>(bytes) + 20, header[3]);
}

// tinygltf loads the file (`bytes`, whose JSON is `json_text`, parsed into raw_). What it is
// given: stand-ins for what it refuses (stand_in_for_tinygltf) and, in a .glb, 1-byte stand-ins
// for the buffers in the BIN chunk, which it would otherwise copy whole; their bytes are read
// where they lie (glb_bin_).
void Reader::load_tinygltf(const unsigned char* bytes, std::size_t size, bool glb, std::string json_text) {
  json patched;
  bool changed = stand_in_for_tinygltf(raw_, glb, &patched);
  const ByteSpan bin = glb ? glb_bin_chunk(bytes, size) : ByteSpan{nullptr, 0};
  const std::vector<std::size_t> in_bin = bin.data ? buffers_in_bin(changed ? patched : raw_, bin.size) : std::vector<std::size_t>();
  if (!in_bin.empty()) {
    if (!changed) patched = raw_;
    changed = true;
    for (const std::size_t b : in_bin) patched["buffers"][b]["byteLength"] = 1;
  }
  if (changed) json_text = patched.dump();
  std::vector<unsigned char> stand_in;
  if (glb && changed) stand_in = glb_with_json(bytes, size, json_text, !in_bin.empty());
  run_tinygltf(glb, changed ? ByteSpan{stand_in.data(), stand_in.size()} : ByteSpan{bytes, size}, json_text);
  glb_bin_.assign(gltf_.buffers.size(), ByteSpan{nullptr, 0});
  for (const std::size_t b : in_bin) glb_bin_[b] = {bin.data, raw_["buffers"][b]["byteLength"].get<std::size_t>()};
}

// tinygltf loads `glb_file` (a .glb) or `json_text` (a .gltf) into gltf_, reading files only
// beside a model read from a file (fs_read).
void Reader::run_tinygltf(bool glb, ByteSpan glb_file, const std::string& json_text) {
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
  const bool ok = glb ? loader.LoadBinaryFromMemory(&gltf_, &err, &warn, glb_file.data,
                                                    static_cast<unsigned>(glb_file.size), base_dir)
                      : loader.LoadASCIIFromString(&gltf_, &err, &warn, json_text.data(),
                                                   static_cast<unsigned>(json_text.size()), base_dir);
  check_tinygltf_errors(ok, err, ctx.error);
}

// The JSON parsed into raw_ and its top level checked, before tinygltf sees it.
void Reader::parse_json(const std::string& json_text) {
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
  for (const char* key : {"accessors", "animations", "buffers", "bufferViews", "cameras", "images", "materials", "meshes",
                          "nodes", "samplers", "scenes", "skins", "textures", "extensionsUsed", "extensionsRequired"})
    if (raw_.contains(key) && !raw_[key].is_array()) fail(std::string("invalid glTF: '") + key + "' is not an array");
  check_uris();
}

// tinygltf 2.7 reports a skin without inverseBindMatrices as an error although the spec makes
// them optional; it still parses the skin (with -1), so that message alone is not a failure.
void Reader::check_tinygltf_errors(bool ok, const std::string& err, const std::string& fs_error) const {
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
  if (!fs_error.empty()) fail(fs_error);
  if (!ok || !real_errors.empty()) fail(real_errors.empty() ? "tinygltf could not parse the file" : real_errors);
}

ByteSpan Reader::buffer_bytes(std::size_t b) const {
  if (b < glb_bin_.size() && glb_bin_[b].data) return glb_bin_[b];
  return {gltf_.buffers[b].data.data(), gltf_.buffers[b].data.size()};
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
  const ByteSpan buf = buffer_bytes(std::size_t(bv.buffer));
  if (bv.byteOffset > buf.size || bv.byteLength > buf.size - bv.byteOffset)
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
  return buf.data + bv.byteOffset + (count > 0 ? offset : 0);
}

// glTF stores little-endian values; reading them in place (Reader::decode) needs a host that does.
#if defined(__BYTE_ORDER__) && defined(__ORDER_LITTLE_ENDIAN__)
static_assert(__BYTE_ORDER__ == __ORDER_LITTLE_ENDIAN__, "the glTF reader reads little-endian file bytes in place");
#endif

AccessorBytes Reader::accessor_bytes(int index, const char* what_c, const std::string& what, std::size_t value_size,
                                     int* components_out) {
  if (index < 0 || static_cast<std::size_t>(index) >= gltf_.accessors.size())
    fail(std::string(what_c) + ": accessor " + std::to_string(index) + " does not exist");
  AccessorBytes in;
  in.acc = &gltf_.accessors[index];
  const auto& acc = *in.acc;
  switch (acc.type) {
    case TINYGLTF_TYPE_SCALAR: in.comps = 1; break;
    case TINYGLTF_TYPE_VEC2: in.comps = 2; break;
    case TINYGLTF_TYPE_VEC3: in.comps = 3; break;
    case TINYGLTF_TYPE_VEC4: in.comps = 4; break;
    case TINYGLTF_TYPE_MAT2: in.comps = 4; break;
    case TINYGLTF_TYPE_MAT3: in.comps = 9; break;
    case TINYGLTF_TYPE_MAT4: in.comps = 16; break;
    default: fail(what + ": unknown type");
  }
  in.csize = component_size(acc.componentType);
  if (in.csize == 0) fail(what + ": unknown componentType " + std::to_string(acc.componentType));
  if (acc.count > kMaxAccessorElements) fail(what + ": count " + std::to_string(acc.count) + " is implausibly large");
  if (components_out) *components_out = in.comps;
  in.elem = std::size_t(in.comps) * std::size_t(in.csize);

  // Every claim is checked against the bytes that back it before anything is allocated: a tiny
  // file may claim millions of elements.
  in.stride = in.elem;
  if (acc.bufferView >= 0) {
    if (static_cast<std::size_t>(acc.bufferView) >= gltf_.bufferViews.size())
      fail(what + ": bufferView " + std::to_string(acc.bufferView) + " does not exist");
    const auto& bv = gltf_.bufferViews[acc.bufferView];
    if (bv.byteStride) in.stride = bv.byteStride;
    if (in.stride < in.elem) fail(what + ": byteStride " + std::to_string(in.stride) + " is smaller than an element");
    in.base = view_bytes(acc.bufferView, acc.byteOffset, in.stride, in.elem, acc.count, what);
  }
  const std::size_t decoded_bytes = acc.count * std::size_t(in.comps) * value_size;  // <= 2^28 * 16 * 4
  if (decoded_bytes > decode_left_)
    fail(what + ": decoding " + std::to_string(acc.count) + " elements" +
         (acc.bufferView < 0 ? " (no bufferView: zeros)" : "") + " would take the model past " +
         std::to_string(kDecodeBaseBytes >> 20) + " MiB plus " + std::to_string(kDecodePerInputByte) +
         " times its input size; the file claims far more data than it holds");
  decode_left_ -= decoded_bytes;
  const auto& sp = acc.sparse;
  if (sp.isSparse) {
    in.sparse = static_cast<std::size_t>(std::max(sp.count, 0));
    if (sp.count < 0 || in.sparse > acc.count) fail(what + ": sparse count " + std::to_string(sp.count) + " is out of range");
    in.isize = component_size(sp.indices.componentType);
    if (in.isize == 0 || sp.indices.componentType == kFloat) fail(what + ": sparse indices have a bad componentType");
    if (sp.indices.byteOffset < 0 || sp.values.byteOffset < 0) fail(what + ": sparse byteOffset is negative");
    in.ibase = view_bytes(sp.indices.bufferView, std::size_t(sp.indices.byteOffset), std::size_t(in.isize),
                          std::size_t(in.isize), in.sparse, what + " sparse indices");
    in.vbase = view_bytes(sp.values.bufferView, std::size_t(sp.values.byteOffset), in.elem, in.elem, in.sparse,
                          what + " sparse values");
  }
  return in;
}

std::vector<std::size_t> Reader::sparse_targets(const AccessorBytes& in, const std::string& what) const {
  std::vector<std::size_t> targets(in.sparse);
  for (std::size_t i = 0; i < in.sparse; ++i) {
    std::uint32_t idx = 0;
    if (in.isize == 1) idx = in.ibase[i];
    else if (in.isize == 2) { std::uint16_t v; std::memcpy(&v, in.ibase + 2 * i, 2); idx = v; }
    else std::memcpy(&idx, in.ibase + 4 * i, 4);
    if (idx >= in.acc->count) fail(what + ": sparse index " + std::to_string(idx) + " is out of range");
    targets[i] = idx;
  }
  return targets;
}

template <class T, class Convert>
Decoded<T> Reader::decode(int index, const char* what_c, int* components_out, Convert convert) {
  const std::string what = std::string(what_c) + " (accessor " + std::to_string(index) + ")";
  const AccessorBytes in = accessor_bytes(index, what_c, what, sizeof(T), components_out);
  const auto& acc = *in.acc;
  const int comps = in.comps;
  const std::size_t stride = in.stride, elem = in.elem;
  const unsigned char* base = in.base;

  // Elements that are the decoded type already (floats to floats, 32-bit indices) are taken as
  // they are: where the file holds them when packed and aligned, else copied; the rest converted.
  const bool raw = (std::is_same<T, float>::value && acc.componentType == kFloat) ||
                   (std::is_same<T, std::uint32_t>::value && acc.componentType == kUnsignedInt);
  if (base && raw && stride == elem && !in.sparse && reinterpret_cast<std::uintptr_t>(base) % alignof(T) == 0)
    // Aligned file bytes that hold little-endian Ts (the host's order, asserted above) are those Ts.
    return Decoded<T>(reinterpret_cast<const T*>(base), acc.count * std::size_t(comps));
  // Backed by a bufferView, every element is written below; otherwise they are zeros.
  detail::UninitVector<T> out;
  if (base) out.resize(acc.count * std::size_t(comps));
  else out.resize(acc.count * std::size_t(comps), T(0));
  // The component type is a constant inside each loop (one loop per type), so the converter's
  // switch folds away instead of running for every component.
  auto load_as = [&](auto type, const unsigned char* from, std::size_t step, std::size_t count, auto&& dst_index) {
    for (std::size_t i = 0; i < count; ++i) {
      const unsigned char* p = from + i * step;
      const std::size_t d = dst_index(i);
      for (int c = 0; c < comps; ++c) out[d * comps + c] = convert(p + std::size_t(c) * in.csize, type(), acc.normalized);
    }
  };
  auto load = [&](const unsigned char* from, std::size_t step, std::size_t count, auto&& dst_index) {
    switch (acc.componentType) {
      case kFloat: return load_as(std::integral_constant<int, kFloat>(), from, step, count, dst_index);
      case kByte: return load_as(std::integral_constant<int, kByte>(), from, step, count, dst_index);
      case kUnsignedByte: return load_as(std::integral_constant<int, kUnsignedByte>(), from, step, count, dst_index);
      case kShort: return load_as(std::integral_constant<int, kShort>(), from, step, count, dst_index);
      case kUnsignedShort: return load_as(std::integral_constant<int, kUnsignedShort>(), from, step, count, dst_index);
      default: return load_as(std::integral_constant<int, kUnsignedInt>(), from, step, count, dst_index);
    }
  };
  if (base) {
    // In parallel chunks, each writing its own elements.
    parallel_for(acc.count, kDecodeGrain, [&](std::size_t b, std::size_t e) {
      if (raw && stride == elem) {
        std::memcpy(out.data() + b * comps, base + b * stride, (e - b) * elem);
      } else if (raw) {
        for (std::size_t i = b; i < e; ++i) std::memcpy(out.data() + i * comps, base + i * stride, elem);
      } else {
        load(base + b * stride, stride, e - b, [b](std::size_t i) { return b + i; });
      }
    });
  }
  if (in.sparse) {
    const std::vector<std::size_t> targets = sparse_targets(in, what);
    load(in.vbase, elem, in.sparse, [&](std::size_t i) { return targets[i]; });
  }
  return Decoded<T>(std::move(out));
}

namespace {

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

}  // namespace

// The converters go in as lambdas, not function pointers, so the decode loop inlines them.
Floats Reader::read_floats(int accessor, const char* what, int* components_out) {
  return decode<float>(accessor, what, components_out,
                       [](const unsigned char* p, int type, bool normalized) { return to_float(p, type, normalized); });
}

Uints Reader::read_uints(int accessor, const char* what, int* components_out) {
  return decode<std::uint32_t>(accessor, what, components_out,
                               [](const unsigned char* p, int type, bool normalized) { return to_uint(p, type, normalized); });
}

Model Reader::read() {
  parse_container();
  decode_meshopt_views();
  decode_draco_primitives();
  read_nodes();
  read_skins();
  read_animations();
  read_images();
  read_passthrough();
  note_dropped_extensions();
  read_meshes();
  resolve_morph_weights();
  return std::move(model_);
}

}  // namespace deepcut::gltf_detail

namespace deepcut {

using gltf_detail::one_line;
using gltf_detail::Reader;

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

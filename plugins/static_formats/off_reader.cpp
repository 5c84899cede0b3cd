// SPDX-License-Identifier: MIT
// OFF (Object File Format, Geomview): VTK 9.1 has no reader for it. The text is split into lines
// (comments dropped), and every count, number and index is checked before it is used.
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <string_view>

#include "deepcut/core/errors.h"
#include "deepcut/plugins/static_formats.h"

namespace deepcut::plugins {
namespace {

// The largest polygon a face line may list: generous for real files, and a bound on the work a
// hostile line can ask for.
constexpr std::size_t kMaxPolygon = 1u << 16;

class OffParser {
 public:
  OffParser(const std::string& text, const std::string& file) : text_(text), file_(file) {}

  StaticMesh parse();

 private:
  // What the header says: the per-vertex data after the position, and the counts.
  struct Header {
    bool has_uv = false, has_color = false, has_normal = false;
    std::size_t vertices = 0, faces = 0;
  };
  Header read_header();
  void read_vertex(const Header& header, StaticMesh& mesh);
  // Face `f`'s polygon, as a triangle fan. Returns whether it had more than three corners.
  bool read_face(std::size_t f, std::size_t vertices, StaticMesh& mesh);

  [[noreturn]] void fail(const std::string& what) const {
    throw Error(ErrorCode::InvalidInput, file_ + ": " + what + (line_no_ ? " (line " + std::to_string(line_no_) + ")" : ""));
  }
  // The next line with something on it, comments stripped, split into tokens. False at the end.
  bool next_line();
  double number(std::size_t token, const char* what) const;
  std::size_t count(std::size_t token, const char* what) const;

  const std::string& text_;
  const std::string& file_;
  std::size_t pos_ = 0, line_no_ = 0;
  std::vector<std::string_view> tokens_;
};

bool OffParser::next_line() {
  while (pos_ < text_.size()) {
    std::size_t end = text_.find('\n', pos_);
    if (end == std::string::npos) end = text_.size();
    std::string_view line(text_.data() + pos_, end - pos_);
    pos_ = end + 1;
    ++line_no_;
    const std::size_t hash = line.find('#');
    if (hash != std::string_view::npos) line = line.substr(0, hash);
    tokens_.clear();
    std::size_t i = 0;
    while (i < line.size()) {
      while (i < line.size() && (line[i] == ' ' || line[i] == '\t' || line[i] == '\r' || line[i] == '\f' || line[i] == '\v')) ++i;
      const std::size_t start = i;
      while (i < line.size() && !(line[i] == ' ' || line[i] == '\t' || line[i] == '\r' || line[i] == '\f' || line[i] == '\v')) ++i;
      if (i > start) tokens_.push_back(line.substr(start, i - start));
    }
    if (!tokens_.empty()) return true;
  }
  tokens_.clear();
  return false;
}

double OffParser::number(std::size_t token, const char* what) const {
  if (token >= tokens_.size()) fail(std::string("a ") + what + " line has too few numbers");
  const std::string s(tokens_[token]);
  char* end = nullptr;
  errno = 0;
  const double v = std::strtod(s.c_str(), &end);
  if (end == s.c_str() || *end != '\0') fail("'" + s.substr(0, 32) + "' is not a number");
  return v;
}

std::size_t OffParser::count(std::size_t token, const char* what) const {
  if (token >= tokens_.size()) fail(std::string("the header has no ") + what + " count");
  const std::string s(tokens_[token]);
  char* end = nullptr;
  errno = 0;
  const long long v = std::strtoll(s.c_str(), &end, 10);
  if (end == s.c_str() || *end != '\0' || errno == ERANGE || v < 0)
    fail(std::string("the ") + what + " count '" + s.substr(0, 32) + "' is not a whole number >= 0");
  return static_cast<std::size_t>(v);
}

OffParser::Header OffParser::read_header() {
  if (text_.empty()) fail("file is empty");
  if (!next_line()) fail("no OFF header (the file holds only comments or blank lines)");
  // Header keyword: [ST][C][N][4][n]OFF. Counts may follow on the same line.
  Header h;
  std::size_t first_count = 0;
  const std::string_view key = tokens_[0];
  if (key.size() >= 3 && key.substr(key.size() - 3) == "OFF") {
    std::string_view prefix = key.substr(0, key.size() - 3);
    if (prefix.substr(0, 2) == "ST") {
      h.has_uv = true;
      prefix.remove_prefix(2);
    }
    if (!prefix.empty() && prefix[0] == 'C') {
      h.has_color = true;
      prefix.remove_prefix(1);
    }
    if (!prefix.empty() && prefix[0] == 'N') {
      h.has_normal = true;
      prefix.remove_prefix(1);
    }
    if (!prefix.empty())
      fail("header '" + std::string(key.substr(0, 32)) + "' is not supported (only 3D [ST][C][N]OFF)");
    first_count = 1;
    if (tokens_.size() == 1) {  // the counts are on the next line
      if (!next_line()) fail("truncated: no vertex and face counts after the header");
      first_count = 0;
    }
  } else if (!(key[0] >= '0' && key[0] <= '9')) {
    fail("does not start with an OFF header");
  }
  h.vertices = count(first_count, "vertex");
  h.faces = count(first_count + 1, "face");
  // Each vertex needs at least three one-character numbers and separators, each face at least
  // four: counts past that cannot be in the file, and nothing is reserved for them.
  if (h.vertices > text_.size() / 6)
    fail("the header claims " + std::to_string(h.vertices) + " vertices; the file is only " +
         std::to_string(text_.size()) + " bytes");
  if (h.faces > text_.size() / 8)
    fail("the header claims " + std::to_string(h.faces) + " faces; the file is only " +
         std::to_string(text_.size()) + " bytes");
  return h;
}

void OffParser::read_vertex(const Header& header, StaticMesh& mesh) {
  std::size_t t = 0;
  glm::vec3 p;
  for (int c = 0; c < 3; ++c) p[c] = static_cast<float>(number(t++, "vertex"));
  mesh.positions.push_back(p);
  if (header.has_normal) {
    glm::vec3 n;
    for (int c = 0; c < 3; ++c) n[c] = static_cast<float>(number(t++, "vertex"));
    mesh.normals.push_back(n);
  }
  if (header.has_color) {
    // 3 or 4 components; integers 0..255 when any is above 1.
    const std::size_t left = tokens_.size() - t - (header.has_uv ? 2 : 0);
    const std::size_t comps = left >= 4 ? 4 : 3;
    glm::vec4 c(1.0f);
    for (std::size_t k = 0; k < comps; ++k) c[int(k)] = static_cast<float>(number(t++, "vertex"));
    if (c.r > 1.0f || c.g > 1.0f || c.b > 1.0f || (comps == 4 && c.a > 1.0f)) c /= 255.0f;
    if (comps == 3) c.a = 1.0f;
    mesh.colors.push_back(c);
  }
  if (header.has_uv) {
    glm::vec2 uv;
    for (int c = 0; c < 2; ++c) uv[c] = static_cast<float>(number(t++, "vertex"));
    mesh.uvs.push_back(uv);
  }
}

bool OffParser::read_face(std::size_t f, std::size_t vertices, StaticMesh& mesh) {
  const double k = number(0, "face");
  if (!(k >= 3.0 && k <= double(kMaxPolygon)) || k != std::floor(k))
    fail("face " + std::to_string(f) + " has " + std::string(tokens_[0].substr(0, 32)) +
         " corners (a face needs a whole number from 3 to " + std::to_string(kMaxPolygon) + ")");
  const std::size_t corners = static_cast<std::size_t>(k);
  if (tokens_.size() < corners + 1)
    fail("face " + std::to_string(f) + " lists " + std::to_string(tokens_.size() - 1) + " of its " +
         std::to_string(corners) + " corners");
  std::vector<std::uint32_t> ids(corners);
  for (std::size_t c = 0; c < corners; ++c) {
    const double id = number(c + 1, "face");
    if (!(id >= 0.0) || id != std::floor(id) || id >= double(vertices))
      fail("face " + std::to_string(f) + " uses vertex " + std::string(tokens_[c + 1].substr(0, 32)) +
           ", past the " + std::to_string(vertices) + " vertices");
    ids[c] = static_cast<std::uint32_t>(id);
  }
  for (std::size_t c = 1; c + 1 < corners; ++c) mesh.triangles.push_back({ids[0], ids[c], ids[c + 1]});
  return corners > 3;
}

StaticMesh OffParser::parse() {
  const Header header = read_header();
  const std::size_t nv = header.vertices, nf = header.faces;
  StaticMesh mesh;
  mesh.positions.reserve(nv);
  if (header.has_normal) mesh.normals.reserve(nv);
  if (header.has_color) mesh.colors.reserve(nv);
  if (header.has_uv) mesh.uvs.reserve(nv);
  for (std::size_t i = 0; i < nv; ++i) {
    if (!next_line()) fail("truncated: the header claims " + std::to_string(nv) + " vertices, the file holds " + std::to_string(i));
    read_vertex(header, mesh);
  }
  std::size_t polygons = 0;
  mesh.triangles.reserve(nf);
  for (std::size_t f = 0; f < nf; ++f) {
    if (!next_line()) fail("truncated: the header claims " + std::to_string(nf) + " faces, the file holds " + std::to_string(f));
    if (read_face(f, nv, mesh)) ++polygons;
  }
  if (polygons) mesh.problems.push_back({"polygons-triangulated", std::to_string(polygons) + (polygons == 1 ? " polygon" : " polygons") + " split into triangle fans", polygons, {}});
  return mesh;
}

}  // namespace

StaticMesh parse_off(const std::string& text, const std::string& file) { return OffParser(text, file).parse(); }

}  // namespace deepcut::plugins

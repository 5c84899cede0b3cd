// SPDX-License-Identifier: MIT
// OBJ, PLY and STL through VTK's readers, OFF through parse_off; each becomes a StaticMesh and
// then an unrigged Model (make_static_model). The checks VTK does not do happen here: the file is
// looked at before a reader opens it (a size a header's counts must fit), VTK's messages are
// captured instead of printed, and every cell's point ids are checked before a filter uses them.
#include "deepcut/plugins/static_formats.h"

#include <sys/stat.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>

#include <vtkCellArray.h>
#include <vtkDataArray.h>
#include <vtkLogger.h>
#include <vtkNew.h>
#include <vtkOBJReader.h>
#include <vtkOutputWindow.h>
#include <vtkPLYReader.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkSTLReader.h>
#include <vtkSmartPointer.h>
#include <vtkTriangleFilter.h>
#include <vtkUnsignedCharArray.h>

#include "deepcut/core/errors.h"

namespace deepcut::plugins {
namespace {

constexpr std::uintmax_t kMaxFileBytes = std::uintmax_t(2) << 30;  // 2 GiB, as for glTF

/// Collects what VTK would print (errors and warnings), so a bad file gives one line of ours.
class CapturingOutputWindow : public vtkOutputWindow {
 public:
  static CapturingOutputWindow* New();
  vtkTypeMacro(CapturingOutputWindow, vtkOutputWindow)

  void DisplayText(const char* text) override { keep(text, warnings_); }
  void DisplayErrorText(const char* text) override { keep(text, errors_); }
  void DisplayWarningText(const char* text) override { keep(text, warnings_); }
  void DisplayGenericWarningText(const char* text) override { keep(text, warnings_); }
  void DisplayDebugText(const char*) override {}

  const std::vector<std::string>& errors() const { return errors_; }
  const std::vector<std::string>& warnings() const { return warnings_; }

 private:
  // VTK's text is "ERROR: In FILE, line N\nvtkClass (0x...): message\n\n": keep the message.
  static void keep(const char* text, std::vector<std::string>& into) {
    if (!text || into.size() >= 16) return;
    std::string s(text);
    const std::size_t close = s.find("): ");
    if (close != std::string::npos) s = s.substr(close + 3);
    // VTK quotes the offending line, which may be binary: printable ASCII only, and short.
    if (s.size() > 120) s = s.substr(0, 120) + "...";
    for (char& c : s)
      if (static_cast<unsigned char>(c) < 0x20 || static_cast<unsigned char>(c) > 0x7E) c = c == '\n' ? ' ' : '?';
    while (!s.empty() && s.back() == ' ') s.pop_back();
    if (!s.empty()) into.push_back(s);
  }
  std::vector<std::string> errors_, warnings_;
};
vtkStandardNewMacro(CapturingOutputWindow);

/// Installs a capturing output window for its lifetime (VTK's output window is process-wide).
class CaptureVtkMessages {
 public:
  // VTK 9 logs errors to stderr through vtkLogger before the output window sees them: that
  // channel is closed for the duration too.
  CaptureVtkMessages() : previous_(vtkOutputWindow::GetInstance()), verbosity_(vtkLogger::GetCurrentVerbosityCutoff()) {
    vtkOutputWindow::SetInstance(window_);
    vtkLogger::SetStderrVerbosity(vtkLogger::VERBOSITY_OFF);
  }
  ~CaptureVtkMessages() {
    vtkLogger::SetStderrVerbosity(verbosity_);
    vtkOutputWindow::SetInstance(previous_);
  }
  CaptureVtkMessages(const CaptureVtkMessages&) = delete;
  CaptureVtkMessages& operator=(const CaptureVtkMessages&) = delete;
  const CapturingOutputWindow& messages() const { return *window_; }

 private:
  vtkSmartPointer<vtkOutputWindow> previous_;
  vtkLogger::Verbosity verbosity_;
  vtkNew<CapturingOutputWindow> window_;
};

std::string lower(std::string s) {
  for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

[[noreturn]] void fail(const std::string& path, const std::string& what) {
  throw Error(ErrorCode::InvalidInput, path + ": " + what);
}

/// The checks every file gets before a reader opens it. @returns the file's size.
std::uintmax_t check_file(const std::string& path) {
  struct stat st{};
  if (::stat(path.c_str(), &st) != 0) {
    if (errno == ENOENT) throw Error(ErrorCode::Io, path + ": no such file");
    throw Error(ErrorCode::Io, path + ": cannot open (" + std::strerror(errno) + ")");
  }
  if (S_ISDIR(st.st_mode)) throw Error(ErrorCode::Io, path + ": is a directory, not a model file");
  // A FIFO or device would block or never end: only regular files (or symlinks to them) are read.
  if (!S_ISREG(st.st_mode)) throw Error(ErrorCode::Io, path + ": is not a regular file");
  if (st.st_size == 0) fail(path, "file is empty");
  if (static_cast<std::uintmax_t>(st.st_size) > kMaxFileBytes) fail(path, "file is larger than 2 GiB");
  std::ifstream probe(path, std::ios::binary);
  if (!probe) throw Error(ErrorCode::Io, path + ": cannot open (" + std::strerror(errno) + ")");
  return static_cast<std::uintmax_t>(st.st_size);
}

std::string read_head(const std::string& path, std::size_t bytes) {
  std::ifstream in(path, std::ios::binary);
  std::string head(bytes, '\0');
  in.read(head.data(), static_cast<std::streamsize>(bytes));
  head.resize(static_cast<std::size_t>(in.gcount()));
  return head;
}

/// A PLY header as parsed: the format, the elements with their properties, and where the body
/// starts.
struct PlyProperty {
  std::string name;
  bool list = false;
  int count_size = 0;  // list: bytes of the count
  bool count_signed = false;
  int size = 0;  // scalar bytes, or bytes per list item
  bool item_signed = false;
  bool vertex_ids = false;  // a face's vertex_indices: each checked against the vertex count
};
struct PlyElement {
  std::string name;
  std::uintmax_t count = 0;
  std::vector<PlyProperty> properties;
};

struct PlyHeader {
  std::string format;
  std::vector<PlyElement> elements;
  std::size_t body = 0;  // offset of the first byte after the header
};

// Bytes of a PLY scalar type (and whether it is signed); `integer`: a list count or index type.
int ply_type_size(const std::string& path, const std::string& t, bool* is_signed = nullptr, bool integer = false) {
  if (is_signed) *is_signed = t == "char" || t == "int8" || t == "short" || t == "int16" || t == "int" || t == "int32";
  if (t == "char" || t == "uchar" || t == "int8" || t == "uint8") return 1;
  if (t == "short" || t == "ushort" || t == "int16" || t == "uint16") return 2;
  if (t == "int" || t == "uint" || t == "int32" || t == "uint32") return 4;
  if (!integer && (t == "float" || t == "float32")) return 4;
  if (!integer && (t == "double" || t == "float64")) return 8;
  fail(path, "PLY property type '" + t.substr(0, 32) + (integer ? "' cannot count a list" : "' is unknown"));
}

// Where the header in `head` ends (after its "end_header" line's '\n'), and `*body`, where the
// body starts. The header ends with a line that is exactly "end_header" (vtkPLY reads on into the
// binary body otherwise), and holds printable text only.
std::size_t ply_header_end(const std::string& path, const std::string& head, std::size_t* body) {
  std::size_t end = std::string::npos;
  for (const char* marker : {"\nend_header\n", "\nend_header\r\n"}) {
    const std::size_t at = head.find(marker);
    if (at != std::string::npos && at < end) {
      end = at + 1;
      *body = at + std::strlen(marker);
    }
  }
  if (end == std::string::npos) fail(path, "no 'end_header' line in the first 64 KiB (truncated or not a PLY header)");
  for (std::size_t i = 0; i < end; ++i) {
    const auto c = static_cast<unsigned char>(head[i]);
    if ((c < 0x20 && c != '\n' && c != '\r' && c != '\t') || c >= 0x7F)
      fail(path, "the PLY header holds a byte that is not text (offset " + std::to_string(i) + ")");
  }
  return end;
}

// An "element NAME COUNT" line's element, after its first word.
PlyElement read_ply_element(const std::string& path, std::istringstream& words) {
  PlyElement e;
  std::string count;
  words >> e.name >> count;
  if (count.empty() || count.size() > 12 ||
      !std::all_of(count.begin(), count.end(), [](char c) { return c >= '0' && c <= '9'; }))
    fail(path, "PLY element '" + e.name.substr(0, 32) + "' has no whole-number count");
  e.count = std::stoull(count);
  return e;
}

// A "property TYPE NAME" or "property list COUNT_TYPE ITEM_TYPE NAME" line's property of element
// `e`, after its first word.
PlyProperty read_ply_property(const std::string& path, std::istringstream& words, const PlyElement& e) {
  std::string type;
  words >> type;
  PlyProperty prop;
  if (type == "list") {
    std::string count_type, item_type;
    words >> count_type >> item_type >> prop.name;
    prop.list = true;
    prop.count_size = ply_type_size(path, count_type, &prop.count_signed, true);
    prop.vertex_ids = e.name == "face" && (prop.name == "vertex_indices" || prop.name == "vertex_index");
    prop.size = ply_type_size(path, item_type, &prop.item_signed, prop.vertex_ids);
  } else {
    words >> prop.name;
    prop.size = ply_type_size(path, type);
  }
  return prop;
}

// One header line into `header`.
void read_ply_header_line(const std::string& path, const std::string& line, PlyHeader& header) {
  if (line.size() > 1000) fail(path, "a PLY header line is longer than 1000 characters");
  std::vector<PlyElement>& elements = header.elements;
  std::istringstream words(line);
  std::string word;
  words >> word;
  if (word == "format") {
    words >> header.format;
    if (header.format != "ascii" && header.format != "binary_little_endian" &&
        header.format != "binary_big_endian")
      fail(path, "PLY format '" + header.format.substr(0, 32) + "' is unknown");
  } else if (word == "element") {
    elements.push_back(read_ply_element(path, words));
    if (elements.size() > 64) fail(path, "the PLY header declares more than 64 elements");
  } else if (word == "property") {
    if (elements.empty()) fail(path, "a PLY property comes before any element");
    PlyElement& e = elements.back();
    if (e.properties.size() >= 256)
      fail(path, "PLY element '" + e.name.substr(0, 32) + "' has more than 256 properties");
    e.properties.push_back(read_ply_property(path, words, e));
  } else if (!word.empty() && word != "comment" && word != "obj_info" && word != "ply") {
    // vtkPLY's header parser misreads lines it does not know (a fuzzer crashed it).
    fail(path,
         "the PLY header line '" + line.substr(0, 32) + "' is not format, element, property or comment");
  }
}

// The header: short printable lines, known types, at most 64 elements of 256 properties.
PlyHeader parse_ply_header(const std::string& path) {
  const std::string head = read_head(path, 64 * 1024);
  if (head.compare(0, 3, "ply") != 0 || (head.size() > 3 && head[3] != '\n' && head[3] != '\r'))
    fail(path, "does not start with 'ply'");
  PlyHeader header;
  const std::size_t end = ply_header_end(path, head, &header.body);
  std::istringstream lines(head.substr(0, end));
  std::string line;
  while (std::getline(lines, line)) read_ply_header_line(path, line, header);
  if (header.format.empty()) fail(path, "the PLY header has no format line");
  return header;
}

// vtkPLYReader needs vertices with x, y and z and faces with a vertex index list, and every
// element must fit in the bytes after the header.
void check_ply_elements(const std::string& path, const PlyHeader& header, std::uintmax_t size) {
  const auto& elements = header.elements;
  const auto& format = header.format;
  const std::size_t body = header.body;
  const auto find = [&](const char* name) -> const PlyElement* {
    for (const PlyElement& e : elements)
      if (e.name == name) return &e;
    return nullptr;
  };
  const PlyElement* vertex = find("vertex");
  const PlyElement* face = find("face");
  const auto has = [](const PlyElement* e, const char* name, bool list) {
    return e && std::any_of(e->properties.begin(), e->properties.end(),
                            [&](const PlyProperty& p) { return p.name == name && p.list == list; });
  };
  if (!has(vertex, "x", false) || !has(vertex, "y", false) || !has(vertex, "z", false))
    fail(path, "the PLY header has no vertex element with x, y and z");
  if (!has(face, "vertex_indices", true) && !has(face, "vertex_index", true))
    fail(path, "no faces (the PLY header has no face element with a vertex_indices list)");
  const std::uintmax_t left = size > body ? size - body : 0;
  for (const PlyElement& e : elements) {
    if (e.properties.empty() && e.count > 0) fail(path, "PLY element '" + e.name.substr(0, 32) + "' has no properties");
    // At least one byte per property per element (ASCII: a character and a separator).
    const std::uintmax_t per = (format == "ascii" ? 2 : 1) * std::max<std::uintmax_t>(e.properties.size(), 1);
    if (e.count > (left + 1) / per)
      fail(path, "the PLY header claims " + std::to_string(e.count) + " " + e.name.substr(0, 32) + " elements; the file holds " +
                     std::to_string(left) + " bytes after its header");
  }
}

[[noreturn]] void ply_truncated(const std::string& path, const PlyElement& e, std::uintmax_t i) {
  fail(path, "truncated PLY: " + e.name.substr(0, 32) + " " + std::to_string(i) + " of " + std::to_string(e.count) +
                 " is missing or incomplete");
}

[[noreturn]] void ply_bad_id(const std::string& path, const PlyElement& e, std::uintmax_t i, long long id, long long vertices) {
  fail(path, e.name.substr(0, 32) + " " + std::to_string(i) + " uses vertex " + std::to_string(id) + ", past the " +
                 std::to_string(vertices) + " vertices");
}

// An ASCII body: vtkPLY reads one element per line, so each line must hold all of its element's
// values, as numbers, with list lengths in range and vertex ids naming a vertex.
void check_ply_ascii_body(const std::string& path, const PlyHeader& header, long long vertices) {
  std::ifstream in(path, std::ios::binary);
  in.seekg(static_cast<std::streamoff>(header.body));
  std::string row;
  for (const PlyElement& e : header.elements)
    for (std::uintmax_t i = 0; i < e.count; ++i) {
      do {
        if (!std::getline(in, row)) ply_truncated(path, e, i);
      } while (row.find_first_not_of(" \t\r") == std::string::npos);
      // vtkPLY splits lines as C strings: a NUL or another control byte loses words (a crash).
      for (const char ch : row) {
        const auto c = static_cast<unsigned char>(ch);
        if ((c < 0x20 && c != '\t' && c != '\r') || c >= 0x7F)
          fail(path, e.name.substr(0, 32) + " " + std::to_string(i) + ": a byte that is not text in an ASCII PLY");
      }
      std::istringstream words(row);
      std::string word;
      for (const PlyProperty& prop : e.properties) {
        if (!(words >> word)) ply_truncated(path, e, i);
        char* end_of_number = nullptr;
        (void)std::strtod(word.c_str(), &end_of_number);
        if (*end_of_number != '\0')
          fail(path, e.name.substr(0, 32) + " " + std::to_string(i) + ": '" + word.substr(0, 32) + "' is not a number");
        if (!prop.list) continue;
        char* stop = nullptr;
        const long long n = std::strtoll(word.c_str(), &stop, 10);
        if (*stop != '\0' || n < 0 || n > 1 << 20)
          fail(path, e.name.substr(0, 32) + " " + std::to_string(i) + ": list length '" + word.substr(0, 32) + "' is not a whole number from 0 to 2^20");
        for (long long k = 0; k < n; ++k) {
          if (!(words >> word)) ply_truncated(path, e, i);
          if (!prop.vertex_ids) continue;
          const long long id = std::strtoll(word.c_str(), &stop, 10);
          if (*stop != '\0' || id < 0 || id >= vertices) ply_bad_id(path, e, i, id, vertices);
        }
      }
    }
}

// A binary body: list lengths in range, vertex ids naming a vertex, and everything inside the file.
void check_ply_binary_body(const std::string& path, const PlyHeader& header, std::uintmax_t size, long long vertices) {
  std::ifstream in(path, std::ios::binary);
  in.seekg(static_cast<std::streamoff>(header.body));
  const auto& format = header.format;
  const bool big = format == "binary_big_endian";
  std::uintmax_t offset = header.body;
  for (const PlyElement& e : header.elements)
    for (std::uintmax_t i = 0; i < e.count; ++i)
      for (const PlyProperty& prop : e.properties) {
        if (!prop.list) {
          offset += std::uintmax_t(prop.size);
          continue;
        }
        unsigned char b[4] = {};
        in.seekg(static_cast<std::streamoff>(offset));
        if (offset + std::uintmax_t(prop.count_size) > size || !in.read(reinterpret_cast<char*>(b), prop.count_size)) ply_truncated(path, e, i);
        std::uint32_t raw = 0;
        for (int k = 0; k < prop.count_size; ++k) raw |= std::uint32_t(b[big ? prop.count_size - 1 - k : k]) << (8 * k);
        long long n = raw;
        if (prop.count_signed && (raw >> (8 * prop.count_size - 1)) & 1u) n = -1;
        if (n < 0 || n > 1 << 20)
          fail(path, e.name.substr(0, 32) + " " + std::to_string(i) + ": list length is not from 0 to 2^20");
        offset += std::uintmax_t(prop.count_size);
        if (prop.vertex_ids) {
          for (long long k = 0; k < n; ++k, offset += std::uintmax_t(prop.size)) {
            unsigned char v[4] = {};
            if (offset + std::uintmax_t(prop.size) > size || !in.read(reinterpret_cast<char*>(v), prop.size)) ply_truncated(path, e, i);
            std::uint32_t u = 0;
            for (int c = 0; c < prop.size; ++c) u |= std::uint32_t(v[big ? prop.size - 1 - c : c]) << (8 * c);
            long long id = u;
            if (prop.item_signed && (u >> (8 * prop.size - 1)) & 1u) id = static_cast<long long>(u) - (1ll << (8 * prop.size));
            if (id < 0 || id >= vertices) ply_bad_id(path, e, i, id, vertices);
          }
        } else {
          offset += std::uintmax_t(n) * std::uintmax_t(prop.size);
        }
        if (offset > size) ply_truncated(path, e, i);
      }
  if (offset > size) fail(path, "truncated PLY: the elements need " + std::to_string(offset) + " bytes, the file has " + std::to_string(size));
}

/// A PLY file must hold every element its header declares: VTK's PLY code allocates what the
/// header says and reads on past a truncated body (a crash, not an error). So the header is
/// parsed here (short lines, known types, counts that fit the file), then the body is walked
/// element by element, list counts included, before vtkPLYReader opens the file.
void check_ply(const std::string& path, std::uintmax_t size) {
  const PlyHeader header = parse_ply_header(path);
  check_ply_elements(path, header, size);
  // VTK reads the points a face names without checking them: each id must name a vertex.
  long long vertices = 0;
  for (const PlyElement& e : header.elements)
    if (e.name == "vertex") vertices = static_cast<long long>(e.count);
  if (header.format == "ascii")
    check_ply_ascii_body(path, header, vertices);
  else
    check_ply_binary_body(path, header, size, vertices);
}

/// Wavefront OBJ: vtkOBJReader reads "nan" or "1e999" without a word (as 0 or Inf) and follows
/// a face's texture coordinate or normal index past the end of its arrays (a crash). So the file
/// is read here first: every v, vt and vn value must be a finite number, and every index of a
/// face, line or point must name an element defined before it (negative: counted back from there).
void check_obj(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::string line;
  std::uintmax_t line_no = 0;
  long long counts[3] = {0, 0, 0};  // v, vt, vn
  static const char* kinds[3] = {"vertices", "texture coordinates", "normals"};
  while (std::getline(in, line)) {
    ++line_no;
    if (line.size() < 2) continue;
    const char c0 = line[0], c1 = line[1];
    const bool blank1 = c1 == ' ' || c1 == '\t';
    if (c0 == 'v' && (blank1 || ((c1 == 't' || c1 == 'n') && line.size() > 2 && (line[2] == ' ' || line[2] == '\t')))) {
      ++counts[blank1 ? 0 : c1 == 't' ? 1 : 2];
      std::istringstream words(line.substr(blank1 ? 1 : 2));
      std::string word;
      while (words >> word) {
        if (word[0] == '#') break;
        char* stop = nullptr;
        const double v = std::strtod(word.c_str(), &stop);
        if (*stop != '\0' || !std::isfinite(v))
          fail(path, "line " + std::to_string(line_no) + ": '" + word.substr(0, 32) + "' is not a finite number");
      }
      continue;
    }
    if (!((c0 == 'f' || c0 == 'l' || c0 == 'p') && blank1)) continue;
    std::istringstream words(line.substr(1));
    std::string word;
    while (words >> word) {
      if (word[0] == '#') break;
      std::size_t start = 0;
      for (int kind = 0; kind < 3 && start <= word.size(); ++kind) {
        const std::size_t slash = std::min(word.find('/', start), word.size());
        const std::string part = word.substr(start, slash - start);
        start = slash + 1;
        if (part.empty()) {
          if (kind == 0) fail(path, "line " + std::to_string(line_no) + ": '" + word.substr(0, 32) + "' names no vertex");
          continue;
        }
        char* stop = nullptr;
        errno = 0;
        const long long id = std::strtoll(part.c_str(), &stop, 10);
        const long long resolved = id < 0 ? counts[kind] + id + 1 : id;
        if (*stop != '\0' || errno == ERANGE || id == 0 || resolved < 1 || resolved > counts[kind])
          fail(path, "line " + std::to_string(line_no) + ": '" + part.substr(0, 32) + "' is not one of the " +
                         std::to_string(counts[kind]) + " " + kinds[kind] +
                         " defined before it");
        if (slash == word.size()) break;
      }
    }
  }
}

/// A binary STL's triangle count must fit the file (50 bytes per triangle after 84).
void check_stl(const std::string& path, std::uintmax_t size) {
  const std::string head = read_head(path, 256);
  // Text only if it starts with "solid" and its head is printable: VTK takes anything else with
  // control bytes as binary and allocates what bytes 80-83 say (a fuzzer found 9.7 GB asked for).
  const auto printable = [](char ch) {
    const auto c = static_cast<unsigned char>(ch);
    return (c >= 0x20 && c < 0x7F) || c == '\t' || c == '\n' || c == '\r' || c == '\f' || c == '\v';
  };
  const bool text = head.compare(0, 5, "solid") == 0 && std::all_of(head.begin(), head.end(), printable);
  if (text) return;
  if (size < 84) fail(path, "truncated binary STL: " + std::to_string(size) + " bytes, the header alone is 84");
  std::uint32_t count = 0;
  for (int i = 3; i >= 0; --i) count = (count << 8) | static_cast<unsigned char>(head[80 + std::size_t(i)]);
  const std::uintmax_t room = (size - 84) / 50;
  if (count > room)
    fail(path, "truncated binary STL: the header says " + std::to_string(count) + " triangles, the file holds " + std::to_string(room));
  if (count == 0) fail(path, "no faces (the binary STL header says 0 triangles)");
}

/// Throws (naming `path`) unless every id of `data`'s polygons and strips names one of its points;
/// checked before a filter touches them.
void check_face_ids(vtkPolyData* data, const std::string& path) {
  const vtkIdType np = data->GetNumberOfPoints();
  for (vtkCellArray* cells : {data->GetPolys(), data->GetStrips()}) {
    if (!cells) continue;
    const vtkIdType n = cells->GetNumberOfCells();
    for (vtkIdType c = 0; c < n; ++c) {
      vtkIdType size = 0;
      const vtkIdType* ids = nullptr;
      cells->GetCellAtId(c, size, ids);
      for (vtkIdType k = 0; k < size; ++k)
        if (ids[k] < 0 || ids[k] >= np)
          fail(path, "face " + std::to_string(c) + " uses vertex " + std::to_string(ids[k]) + ", past the " +
                         std::to_string(np) + " vertices");
    }
  }
}

/// `data` with its faces as triangles alone: itself when they are, else its polygons and strips
/// triangulated (noted in `problems`).
vtkSmartPointer<vtkPolyData> face_triangles(vtkPolyData* data, std::vector<ImportProblem>& problems) {
  bool only_triangles = data->GetNumberOfStrips() == 0;
  if (vtkCellArray* polys = data->GetPolys(); only_triangles && polys)
    only_triangles = polys->IsHomogeneous() == 3 || polys->GetNumberOfCells() == 0;
  if (only_triangles) return data;
  vtkNew<vtkPolyData> faces;
  faces->SetPoints(data->GetPoints());
  faces->SetPolys(data->GetPolys());
  faces->SetStrips(data->GetStrips());
  faces->GetPointData()->ShallowCopy(data->GetPointData());
  vtkNew<vtkTriangleFilter> triangulate;
  triangulate->SetInputData(faces);
  triangulate->PassVertsOff();
  triangulate->PassLinesOff();
  triangulate->Update();
  vtkSmartPointer<vtkPolyData> tris = triangulate->GetOutput();
  problems.push_back({"polygons-triangulated",
                      std::to_string(data->GetNumberOfPolys() + data->GetNumberOfStrips()) +
                          " polygons and strips triangulated into " +
                          std::to_string(tris->GetNumberOfPolys()) + " triangles",
                      std::size_t(data->GetNumberOfPolys() + data->GetNumberOfStrips()),
                      {}});
  return tris;
}

/// The points and triangles of `tris` into `out` (cells other than triangles are left out).
void read_positions_and_triangles(vtkPolyData* tris, const std::string& path, StaticMesh& out) {
  if (vtkPoints* points = tris->GetPoints()) {
    out.positions.resize(static_cast<std::size_t>(points->GetNumberOfPoints()));
    for (vtkIdType i = 0; i < points->GetNumberOfPoints(); ++i) {
      double p[3];
      points->GetPoint(i, p);
      out.positions[std::size_t(i)] = glm::vec3(static_cast<float>(p[0]), static_cast<float>(p[1]), static_cast<float>(p[2]));
    }
  }
  const vtkIdType points = static_cast<vtkIdType>(out.positions.size());
  vtkCellArray* polys = tris->GetPolys();
  if (!polys) return;
  out.triangles.reserve(static_cast<std::size_t>(polys->GetNumberOfCells()));
  for (vtkIdType c = 0; c < polys->GetNumberOfCells(); ++c) {
    vtkIdType size = 0;
    const vtkIdType* ids = nullptr;
    polys->GetCellAtId(c, size, ids);
    if (size != 3) continue;
    if (std::any_of(ids, ids + 3, [&](vtkIdType id) { return id < 0 || id >= points; }))
      fail(path, "triangle " + std::to_string(c) + " uses a vertex past the " + std::to_string(points) +
                     " vertices");
    out.triangles.push_back({static_cast<std::uint32_t>(ids[0]), static_cast<std::uint32_t>(ids[1]),
                             static_cast<std::uint32_t>(ids[2])});
  }
}

/// The normals, texture coordinates and colours of `pd` (one per point of `out`, else left out)
/// into `out`; byte colours scaled to [0, 1].
void read_point_attributes(vtkPointData* pd, StaticMesh& out) {
  const auto points = static_cast<vtkIdType>(out.positions.size());
  const auto tuples_ok = [&](vtkDataArray* a, int comps) {
    return a && a->GetNumberOfTuples() == points && a->GetNumberOfComponents() >= comps;
  };
  if (vtkDataArray* n = pd->GetNormals(); tuples_ok(n, 3)) {
    out.normals.resize(std::size_t(points));
    for (vtkIdType i = 0; i < points; ++i)
      for (int c = 0; c < 3; ++c) out.normals[std::size_t(i)][c] = static_cast<float>(n->GetComponent(i, c));
  }
  if (vtkDataArray* t = pd->GetTCoords(); tuples_ok(t, 2)) {
    out.uvs.resize(std::size_t(points));
    for (vtkIdType i = 0; i < points; ++i)
      for (int c = 0; c < 2; ++c) out.uvs[std::size_t(i)][c] = static_cast<float>(t->GetComponent(i, c));
  }
  vtkDataArray* colors = pd->GetScalars();
  if (!colors) colors = pd->GetArray("RGB");
  if (!colors) colors = pd->GetArray("RGBA");
  if (tuples_ok(colors, 3) && colors->GetNumberOfComponents() <= 4) {
    const bool bytes = vtkUnsignedCharArray::SafeDownCast(colors) != nullptr;
    const int comps = colors->GetNumberOfComponents();
    out.colors.assign(std::size_t(points), glm::vec4(1.0f));
    for (vtkIdType i = 0; i < points; ++i)
      for (int c = 0; c < comps; ++c)
        out.colors[std::size_t(i)][c] = static_cast<float>(colors->GetComponent(i, c) / (bytes ? 255.0 : 1.0));
  }
}

/// vtkPolyData (polygons and strips; vertices and lines are skipped) to a StaticMesh.
StaticMesh to_static_mesh(vtkPolyData* data, const std::string& path) {
  StaticMesh out;
  check_face_ids(data, path);
  const vtkIdType skipped = data->GetNumberOfVerts() + data->GetNumberOfLines();
  if (skipped > 0)
    out.problems.push_back({"cells-skipped",
                            std::to_string(skipped) + " point and line cells skipped (only faces are kept)",
                            std::size_t(skipped),
                            {}});
  const vtkSmartPointer<vtkPolyData> tris = face_triangles(data, out.problems);
  read_positions_and_triangles(tris, path, out);
  read_point_attributes(tris->GetPointData(), out);
  return out;
}

/// Runs a VTK reader with its messages captured: an error message or a failed update refuses the
/// file with VTK's words.
template <class Reader>
StaticMesh read_with(Reader* reader, const std::string& path) {
  CaptureVtkMessages capture;
  reader->SetFileName(path.c_str());
  reader->Update();
  const bool ok = reader->GetErrorCode() == 0;
  const auto& messages = capture.messages();
  if (!messages.errors().empty()) fail(path, messages.errors().front());
  if (!ok) fail(path, "the reader failed (the file is malformed)");
  StaticMesh mesh = to_static_mesh(reader->GetOutput(), path);
  if (!messages.warnings().empty()) mesh.problems.push_back({"reader-warning", "reader: " + messages.warnings().front(), messages.warnings().size(), {}});
  return mesh;
}

}  // namespace

Model read_static_model(const std::string& path) {
  const std::uintmax_t size = check_file(path);
  const std::filesystem::path p(path);
  const std::string ext = lower(p.extension().string());
  const std::string name = p.stem().string().empty() ? std::string("mesh") : p.stem().string();
  StaticMesh mesh;
  if (ext == ".off") {
    std::ifstream in(path, std::ios::binary);
    std::string text(static_cast<std::size_t>(size), '\0');
    in.read(text.data(), static_cast<std::streamsize>(size));
    if (static_cast<std::uintmax_t>(in.gcount()) != size) throw Error(ErrorCode::Io, path + ": could not read the whole file");
    mesh = parse_off(text, path);
  } else if (ext == ".obj") {
    check_obj(path);
    vtkNew<vtkOBJReader> reader;
    mesh = read_with(reader.GetPointer(), path);
  } else if (ext == ".ply") {
    check_ply(path, size);
    vtkNew<vtkPLYReader> reader;
    mesh = read_with(reader.GetPointer(), path);
  } else if (ext == ".stl") {
    check_stl(path, size);
    vtkNew<vtkSTLReader> reader;
    reader->MergingOff();  // the model welds exact duplicates itself; VTK's locator chokes on NaN
    reader->ScalarTagsOff();
    mesh = read_with(reader.GetPointer(), path);
  } else {
    throw Error(ErrorCode::InvalidArgument, path + ": not a static mesh file (.obj, .ply, .stl, .off)");
  }
  return make_static_model(mesh, name, path);
}

void register_static_formats(FormatRegistry& registry) {
  registry.add({"Wavefront OBJ", {"obj"}, read_static_model});
  registry.add({"PLY", {"ply"}, read_static_model});
  registry.add({"STL", {"stl"}, read_static_model});
  registry.add({"OFF", {"off"}, read_static_model});
}

}  // namespace deepcut::plugins

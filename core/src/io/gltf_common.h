// SPDX-License-Identifier: MIT
#pragma once
// Helpers shared by the glTF reader and writer (private to core).

#include <cstdint>
#include <string>
#include <vector>

#include "uninit_vector.h"

namespace deepcut::gltf_detail {

// glTF component types.
inline constexpr int kByte = 5120, kUnsignedByte = 5121, kShort = 5122, kUnsignedShort = 5123,
                     kUnsignedInt = 5125, kFloat = 5126;

int component_count(const std::string& type);  // "VEC3" -> 3; 0 if unknown
int component_size(int component_type);        // bytes; 0 if unknown

std::string base64_encode(const unsigned char* data, std::size_t size);

// Reads a whole file; throws Error{Io} naming the file when it cannot (Error{InvalidInput} when
// it is over `max_bytes`).
std::vector<unsigned char> read_file(const std::string& path, std::size_t max_bytes);
// The same into a buffer that is not zero-filled first, read in parallel parts (each thread
// copies, and takes the page faults of, its own part): for the model file itself.
detail::UninitVector<unsigned char> read_file_parallel(const std::string& path, std::size_t max_bytes);

// A model file's bytes, read only. Mapped where the system allows it: the pages the file system
// caches are used where they are, neither copied nor preceded by fresh pages the kernel must
// zero; else read (read_file_parallel). The file must not shrink while it is mapped (the pages
// past its new end would fault): a reader holds it only while it reads.
class FileBytes {
 public:
  FileBytes() = default;
  FileBytes(const FileBytes&) = delete;
  FileBytes& operator=(const FileBytes&) = delete;
  ~FileBytes();
  // The file at `path`; throws as read_file does.
  void open(const std::string& path, std::size_t max_bytes);
  const unsigned char* data() const { return data_; }
  std::size_t size() const { return size_; }

 private:
  void* map_ = nullptr;  // the mapping, or null when read into `read_`
  const unsigned char* data_ = nullptr;
  std::size_t size_ = 0;
  detail::UninitVector<unsigned char> read_;
};

// Writes `bytes` to a temporary file beside `path`, flushes it and renames it over `path`.
// Throws Error{Io}; never leaves a partial file at `path`. The temporary is unnamed (O_TMPFILE)
// where the file system allows, so a killed writer leaves no temporary behind either; elsewhere a
// writer killed mid-write leaves a hidden `.<name>.tmp<number>` beside the target. A large unnamed
// temporary is written by the pool's threads in parallel pieces, its blocks reserved first, each
// piece straight to the disk (O_DIRECT) where the file system allows, else through a mapping of
// the file where the file system keeps reserved blocks (ext4, xfs, tmpfs), else with pwrite;
// anything else is written in one stream. The bytes go to the disk as they are
// written and the fsync before the rename waits for the rest; the file replaced is let go on a
// thread of its own (freeing a large file's pages takes long). The folder is flushed after the
// rename, so a crash cannot bring the old file back; when only that flush fails the Error says
// "saved, but the folder could not be flushed" (the new content is in place).
void write_file_atomic(const std::string& path, const std::vector<unsigned char>& bytes);
// The same with the file's bytes given as consecutive parts (a .glb's header and JSON, then its
// binary buffer), written without joining them first.
struct ByteSpan {
  const unsigned char* data;
  std::size_t size;
};
void write_file_atomic(const std::string& path, const std::vector<ByteSpan>& parts);

// Test seam, for tests only: the ways write_file_atomic fills an unnamed temporary. Auto chooses
// as described above. Direct, Mapped and Pwrite force that way for the pieces where the parallel
// write runs (Direct: as far as the file system takes direct writes, the rest as Auto would;
// Mapped: on any file system); Plain forces the one stream. Not thread-safe against concurrent
// writes; a test sets it back to Auto when done.
enum class FillWay : unsigned { Auto = 0, Direct = 1, Mapped = 2, Pwrite = 4, Plain = 8 };
void force_fill_way(FillWay way);
// The ways (FillWay bits) the last unnamed temporary written was filled in; 0 when none was.
unsigned last_fill_ways();

// "file.glb" -> true (case-insensitive extension test).
bool has_extension(const std::string& path, const char* ext);

}  // namespace deepcut::gltf_detail

// SPDX-License-Identifier: MIT
#include "io/gltf_common.h"

#include <fcntl.h>
#include <linux/magic.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <sys/vfs.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <memory>
#include <new>
#include <random>
#include <system_error>
#include <thread>
#include <utility>

#include "deepcut/core/errors.h"
#include "deepcut/core/parallel.h"

namespace deepcut::gltf_detail {

int component_count(const std::string& type) {
  if (type == "SCALAR") return 1;
  if (type == "VEC2") return 2;
  if (type == "VEC3") return 3;
  if (type == "VEC4") return 4;
  if (type == "MAT2") return 4;
  if (type == "MAT3") return 9;
  if (type == "MAT4") return 16;
  return 0;
}

int component_size(int component_type) {
  switch (component_type) {
    case kByte:
    case kUnsignedByte:
      return 1;
    case kShort:
    case kUnsignedShort:
      return 2;
    case kUnsignedInt:
    case kFloat:
      return 4;
    default:
      return 0;
  }
}

std::string base64_encode(const unsigned char* data, std::size_t size) {
  static const char* table = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  out.reserve((size + 2) / 3 * 4);
  std::size_t i = 0;
  for (; i + 2 < size; i += 3) {
    const std::uint32_t n = (std::uint32_t(data[i]) << 16) | (std::uint32_t(data[i + 1]) << 8) | data[i + 2];
    out += table[(n >> 18) & 63];
    out += table[(n >> 12) & 63];
    out += table[(n >> 6) & 63];
    out += table[n & 63];
  }
  if (i < size) {
    std::uint32_t n = std::uint32_t(data[i]) << 16;
    if (i + 1 < size) n |= std::uint32_t(data[i + 1]) << 8;
    out += table[(n >> 18) & 63];
    out += table[(n >> 12) & 63];
    out += i + 1 < size ? table[(n >> 6) & 63] : '=';
    out += '=';
  }
  return out;
}

namespace {

// An open regular file and its size, checked as read_file promises.
struct OpenFile {
  int fd = -1;
  std::size_t size = 0;
  ~OpenFile() {
    if (fd >= 0) ::close(fd);
  }
};

void open_checked(const std::string& path, std::size_t max_bytes, OpenFile& file) {
  std::error_code ec;
  if (!std::filesystem::exists(path, ec)) throw Error(ErrorCode::Io, path + ": no such file");
  if (std::filesystem::is_directory(path, ec)) throw Error(ErrorCode::Io, path + ": is a directory, not a model file");
  // A FIFO or device would block or never end: only regular files (or symlinks to them) are read.
  if (!std::filesystem::is_regular_file(path, ec)) throw Error(ErrorCode::Io, path + ": is not a regular file");
  file.fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
  if (file.fd < 0) throw Error(ErrorCode::Io, path + ": cannot open (" + std::strerror(errno) + ")");
  const off_t end = ::lseek(file.fd, 0, SEEK_END);
  if (end < 0) throw Error(ErrorCode::Io, path + ": read failed");
  file.size = static_cast<std::size_t>(end);
  if (file.size > max_bytes)
    throw Error(ErrorCode::InvalidInput, path + ": file is " + std::to_string(file.size >> 20) + " MiB, over the " +
                                             std::to_string(max_bytes >> 20) + " MiB limit");
}

// Reads bytes [begin, end) of the file into `out + begin`; false when the file ends early or fails.
bool read_range(int fd, unsigned char* out, std::size_t begin, std::size_t end) {
  while (begin < end) {
    const ssize_t n = ::pread(fd, out + begin, end - begin, static_cast<off_t>(begin));
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) return false;
    begin += static_cast<std::size_t>(n);
  }
  return true;
}

}  // namespace

std::vector<unsigned char> read_file(const std::string& path, std::size_t max_bytes) {
  OpenFile file;
  open_checked(path, max_bytes, file);
  std::vector<unsigned char> bytes(file.size);
  if (!read_range(file.fd, bytes.data(), 0, file.size)) throw Error(ErrorCode::Io, path + ": read failed");
  return bytes;
}

detail::UninitVector<unsigned char> read_file_parallel(const std::string& path, std::size_t max_bytes) {
  constexpr std::size_t kPart = std::size_t(4) << 20;
  OpenFile file;
  open_checked(path, max_bytes, file);
  detail::UninitVector<unsigned char> bytes(file.size);
  std::atomic<bool> failed{false};
  parallel_for(file.size, kPart, [&](std::size_t b, std::size_t e) {
    if (!read_range(file.fd, bytes.data(), b, e)) failed = true;
  });
  if (failed) throw Error(ErrorCode::Io, path + ": read failed");
  return bytes;
}

namespace {
#ifdef MAP_POPULATE
constexpr int kPopulate = MAP_POPULATE;
#else
constexpr int kPopulate = 0;
#endif
}  // namespace

FileBytes::~FileBytes() {
  if (map_) ::munmap(map_, size_);
}

void FileBytes::open(const std::string& path, std::size_t max_bytes) {
  {
    OpenFile file;
    open_checked(path, max_bytes, file);
    // Populated at once: the cached pages are entered into the mapping in one call, not faulted
    // in one by one as the reader goes.
    void* map = file.size > 0 ? ::mmap(nullptr, file.size, PROT_READ, MAP_PRIVATE | kPopulate, file.fd, 0) : MAP_FAILED;
    if (map != MAP_FAILED) {
      map_ = map;
      data_ = static_cast<const unsigned char*>(map);
      size_ = file.size;
      return;
    }
  }
  read_ = read_file_parallel(path, max_bytes);
  data_ = read_.data();
  size_ = read_.size();
}

namespace {

// An owned file descriptor (-1: none), closed when it goes out of scope: a throw between the
// open and the close cannot leak it.
class UniqueFd {
 public:
  explicit UniqueFd(int fd = -1) noexcept : fd_(fd) {}
  UniqueFd(const UniqueFd&) = delete;
  UniqueFd& operator=(const UniqueFd&) = delete;
  ~UniqueFd() {
    if (fd_ >= 0) ::close(fd_);
  }
  int get() const noexcept { return fd_; }
  // Closes it now; returns errno when the close fails, else 0.
  int close() noexcept {
    const int fd = std::exchange(fd_, -1);
    return fd >= 0 && ::close(fd) != 0 ? errno : 0;
  }

 private:
  int fd_;
};

// Writes the `size` bytes at `data` where the file stands; returns errno on failure, 0 on success.
int write_range(int fd, const unsigned char* data, std::size_t size) {
  std::size_t done = 0;
  while (done < size) {
    const ssize_t n = ::write(fd, data + done, size - done);
    if (n < 0) {
      if (errno == EINTR) continue;
      return errno;
    }
    if (n == 0) return EIO;  // nothing written for a non-zero size: retrying would spin forever
    done += static_cast<std::size_t>(n);
  }
  return 0;
}

// Writes all of `parts` to `fd` and flushes it to disk; returns errno on failure, 0 on success.
// Written in parts of kSyncPart bytes, each handed to the disk as soon as it is in the file
// (sync_file_range starts its writeback and does not wait), so the disk writes while the next
// part is copied and the fsync that ends the write waits for the last parts only. The fsync
// still decides: the file is on disk only when it returns.
int write_all_and_sync(int fd, const std::vector<ByteSpan>& parts) {
  constexpr std::size_t kSyncPart = std::size_t(16) << 20;
  std::size_t written = 0, synced = 0;
  for (const ByteSpan& part : parts)
    for (std::size_t at = 0; at < part.size;) {
      const std::size_t n = std::min(part.size - at, kSyncPart - (written - synced));
      if (const int err = write_range(fd, part.data + at, n)) return err;
      at += n;
      written += n;
      if (written - synced == kSyncPart) {
#ifdef SYNC_FILE_RANGE_WRITE
        ::sync_file_range(fd, static_cast<off_t>(synced), static_cast<off_t>(kSyncPart),
                          SYNC_FILE_RANGE_WRITE);  // a hint
#endif
        synced = written;
      }
    }
  return ::fsync(fd) != 0 ? errno : 0;
}

// The parallel write: files of at least two pieces, written by more than one thread. 4 MiB is a
// multiple of the page size and of the usual block sizes, not of every one: direct_block checks it
// against the file's.
constexpr std::size_t kPiece = std::size_t(4) << 20;

// The file's bytes [from, to) as consecutive `parts` starting at the offsets `starts`: calls
// `fn(offset, data, size)` for each run of them in order.
template <class Fn>
void each_run(const std::vector<ByteSpan>& parts, const std::vector<std::size_t>& starts, std::size_t from,
              std::size_t to, Fn&& fn) {
  const auto after = std::upper_bound(starts.begin(), starts.end(), from);  // the part holding `from`, + 1
  for (auto i = static_cast<std::size_t>(after - starts.begin()) - 1; i < parts.size() && starts[i] < to;
       ++i) {
    const std::size_t b = std::max(from, starts[i]), e = std::min(to, starts[i + 1]);
    if (b < e) fn(b, parts[i].data + (b - starts[i]), e - b);
  }
}

// pwrite of all `size` bytes at `offset`; returns errno on failure, 0 on success.
int pwrite_all(int fd, const unsigned char* data, std::size_t size, std::size_t offset) {
  for (std::size_t done = 0; done < size;) {
    const ssize_t n = ::pwrite(fd, data + done, size - done, static_cast<off_t>(offset + done));
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) return n < 0 ? errno : EIO;
    done += static_cast<std::size_t>(n);
  }
  return 0;
}

// The block that direct writes to `fd`'s file must be aligned to (offsets, lengths and memory),
// or 0 when the file system takes none (STATX_DIOALIGN) or needs one kPiece is no multiple of.
std::size_t direct_block(int fd) {
#if defined(STATX_DIOALIGN) && defined(O_DIRECT)
  struct statx sx {};
  if (::statx(fd, "", AT_EMPTY_PATH, STATX_DIOALIGN, &sx) != 0 || !(sx.stx_mask & STATX_DIOALIGN) ||
      sx.stx_dio_offset_align == 0 || sx.stx_dio_mem_align == 0)
    return 0;
  // Whole file system blocks too: a direct write of part of an unwritten block is serialised
  // (the file system zeroes the rest of the block under an exclusive lock).
  const std::size_t block =
      std::max<std::size_t>({sx.stx_dio_offset_align, sx.stx_dio_mem_align, sx.stx_blksize,
                             static_cast<std::size_t>(::sysconf(_SC_PAGESIZE))});
  return kPiece % block == 0 ? block : 0;
#else
  (void)fd;
  return 0;
#endif
}

// Whether `fd`'s file system keeps the blocks fallocate reserved for the file until they are
// written (ext4, xfs, tmpfs): only there is a mapped fill kept from faulting for want of space.
// Copy-on-write file systems (btrfs, ZFS, bcachefs) write every block anew and may find no room
// then, and FUSE promises nothing; a fault that fails there kills the process (SIGBUS).
bool keeps_reserved_blocks(int fd) {
  struct statfs fs {};
  if (::fstatfs(fd, &fs) != 0) return false;
  const auto type = static_cast<unsigned long>(fs.f_type);
  return type == EXT4_SUPER_MAGIC || type == XFS_SUPER_MAGIC || type == TMPFS_MAGIC;
}

std::atomic<unsigned> forced_fill_way{0};  // a FillWay (the test seam)
std::atomic<unsigned> fill_ways{0};        // FillWay bits of the last unnamed temporary

void took(FillWay way) { fill_ways.fetch_or(static_cast<unsigned>(way), std::memory_order_relaxed); }

// What the pieces of one parallel write share.
struct ParallelWrite {
  int fd;                                   // the temporary
  int direct;                               // the same file opened O_DIRECT, or -1
  std::size_t block;                        // the alignment of direct writes (when direct >= 0)
  bool map;                                 // fill through a mapping (else pwrite)
  const std::vector<ByteSpan>& parts;       // the file's bytes
  const std::vector<std::size_t>& starts;   // the file offset of each part, then the total
  std::atomic<bool> direct_refused{false};  // EINVAL once: the rest goes through the pages
  std::atomic<int> failed{0};               // the first error, 0 while none
  void fail(int err) {
    int expected = 0;
    failed.compare_exchange_strong(expected, err);
  }
};

// Writes the file's bytes [begin, end) (whole blocks) straight to the disk through an aligned copy
// of them; returns errno on failure, ENOMEM when no copy can be had, 0 on success.
int write_piece_direct(const ParallelWrite& w, std::size_t begin, std::size_t end) {
  struct Free {
    void operator()(unsigned char* p) const { std::free(p); }
  };
  const std::unique_ptr<unsigned char, Free> copy(
      static_cast<unsigned char*>(std::aligned_alloc(w.block, end - begin)));
  if (!copy) return ENOMEM;
  each_run(w.parts, w.starts, begin, end, [&](std::size_t at, const unsigned char* data, std::size_t size) {
    std::memcpy(copy.get() + (at - begin), data, size);
  });
  return pwrite_all(w.direct, copy.get(), end - begin, begin);
}

// Fills the file's bytes [begin, end) (`begin` page-aligned) through a shared mapping of them;
// false when they cannot be mapped (nothing was written then).
bool write_piece_mapped(const ParallelWrite& w, std::size_t begin, std::size_t end) {
  void* map =
      ::mmap(nullptr, end - begin, PROT_READ | PROT_WRITE, MAP_SHARED, w.fd, static_cast<off_t>(begin));
  if (map == MAP_FAILED) return false;
  auto* out = static_cast<unsigned char*>(map);
  each_run(w.parts, w.starts, begin, end, [&](std::size_t at, const unsigned char* data, std::size_t size) {
    std::memcpy(out + (at - begin), data, size);
  });
  ::munmap(map, end - begin);
  return true;
}

// Writes the file's bytes [begin, end) with pwrite; returns errno on failure, 0 on success.
int write_piece_pwrite(const ParallelWrite& w, std::size_t begin, std::size_t end) {
  int err = 0;
  each_run(w.parts, w.starts, begin, end, [&](std::size_t at, const unsigned char* data, std::size_t size) {
    if (!err) err = pwrite_all(w.fd, data, size, at);
  });
  return err;
}

// Writes `parts` (`total` bytes) into `fd` (empty, its offset 0) in pieces of kPiece bytes, one
// task each, in parallel: a write() copies into the file's pages under the file's lock, one
// writer at a time. The file's blocks are reserved first (fallocate). Then each piece goes, as
// far as it spans whole blocks, straight to the disk (O_DIRECT, through an aligned copy of it: no
// page of the file is filled or zeroed; whether direct writes into reserved blocks run side by
// side depends on the kernel: ext4 before about Linux 6.5 takes the file's lock exclusively for a
// direct write into unwritten extents, so there they go one at a time). The rest of it (the
// file's last partial block, or all of it where the file system takes no direct writes) is filled
// through a shared mapping of the file where the file system keeps the reserved blocks
// (keeps_reserved_blocks: a fault there finds its block; only a failing disk could still make it
// fail, with SIGBUS), else with pwrite, and handed to the disk at once
// (sync_file_range, a hint; the fsync after it decides). Returns errno on failure, 0 on success,
// and -1 when the file cannot be reserved for a reason other than space (the caller then writes
// it the plain way; the file is empty again). `way`: Auto, or the way the test seam forces.
int write_parallel(int fd, const std::vector<ByteSpan>& parts, std::size_t total, FillWay way) {
  if (::fallocate(fd, 0, 0, static_cast<off_t>(total)) != 0) {
    const int err = errno;
    if (err == ENOSPC || err == EDQUOT || err == EFBIG) return err;
    return ::ftruncate(fd, 0) == 0 ? -1 : errno;
  }
  // Out of memory here (the offsets, the /proc name, the pool's bookkeeping) is a failed write
  // like any other: the caller reports it naming the file, and the descriptors are closed.
  int failed_with = 0;
  try {
    std::vector<std::size_t> starts(parts.size() + 1, 0);
    for (std::size_t i = 0; i < parts.size(); ++i) starts[i + 1] = starts[i] + parts[i].size;
    const std::size_t block = way == FillWay::Auto || way == FillWay::Direct ? direct_block(fd) : 0;
    int opened = -1;
#ifdef O_DIRECT
    if (block > 0)
      opened = ::open(("/proc/self/fd/" + std::to_string(fd)).c_str(), O_WRONLY | O_DIRECT | O_CLOEXEC);
#endif
    const UniqueFd direct(opened);  // nothing throws between the open and here
    const std::size_t direct_end = direct.get() >= 0 ? total / block * block : 0;  // direct writes end there
    const bool map = way == FillWay::Mapped || (way != FillWay::Pwrite && keeps_reserved_blocks(fd));
    ParallelWrite w{fd, direct.get(), block, map, parts, starts};
    parallel_for((total + kPiece - 1) / kPiece, 1, [&](std::size_t first, std::size_t last) {
      for (std::size_t piece = first; piece < last; ++piece) {
        if (w.failed.load(std::memory_order_relaxed)) return;  // the write has failed: stop writing
        const std::size_t begin = piece * kPiece, end = std::min(total, begin + kPiece);
        std::size_t at = begin;  // [begin, at) is written
        if (const std::size_t to = std::min(end, std::max(begin, direct_end));
            to > begin && !w.direct_refused) {
          const int err = write_piece_direct(w, begin, to);
          if (err == 0) {
            at = to;
            took(FillWay::Direct);
          } else if (err == EINVAL || err == EOPNOTSUPP || err == ENOMEM) {
            w.direct_refused = true;  // this piece and the next ones through the pages
          } else {
            return w.fail(err);
          }
        }
        if (at == end) continue;
        if (w.map && write_piece_mapped(w, at, end)) {
          took(FillWay::Mapped);
        } else {
          if (const int err = write_piece_pwrite(w, at, end)) return w.fail(err);
          took(FillWay::Pwrite);
        }
#ifdef SYNC_FILE_RANGE_WRITE
        ::sync_file_range(fd, static_cast<off_t>(at), static_cast<off_t>(end - at), SYNC_FILE_RANGE_WRITE);
#endif
      }
    });
    failed_with = w.failed.load();
  } catch (const std::bad_alloc&) {
    return ENOMEM;
  }
  if (failed_with) return failed_with;
  return ::fsync(fd) != 0 ? errno : 0;
}

// Writes `parts` to the new unnamed temporary `fd` (open for reading too) and flushes it: in
// parallel where that pays (write_parallel: more than one piece and more than one thread), else
// with write(). Only an unnamed temporary is mapped: no name leads to it, so no other process
// finds it and shrinks it under the mapping (a named one could be truncated by anyone allowed to,
// and the fill would fault). A process of the same user could still open it through
// /proc/<pid>/fd; that is not guarded against.
int write_unnamed_and_sync(int fd, const std::vector<ByteSpan>& parts) {
  std::size_t total = 0;
  for (const ByteSpan& part : parts) total += part.size;
  const auto way = static_cast<FillWay>(forced_fill_way.load());
  fill_ways = 0;
  if (way != FillWay::Plain && total > kPiece && thread_count() > 1)
    if (const int err = write_parallel(fd, parts, total, way); err >= 0) return err;
  took(FillWay::Plain);
  return write_all_and_sync(fd, parts);
}

// Closes `fd` on a thread of its own (on the caller when none can start). Called after a
// successful rename: whatever starting the thread throws (std::system_error, std::bad_alloc), the
// descriptor is closed here and nothing escapes, so the save still reports success.
void close_in_background(int fd) noexcept {
  if (fd < 0) return;
  try {
    std::thread([fd] { ::close(fd); }).detach();
  } catch (...) {
    ::close(fd);
  }
}

// Renames `tmp` over `path`; returns errno on failure (`tmp` is then removed), 0 on success. The
// file `path` named until then is held open across the rename and let go on a thread of its own:
// dropping the last reference to a replaced file frees its pages and blocks, which for a large
// file takes a good part of a second, and the caller need not wait for that.
int replace_file(const std::string& tmp, const std::string& path) {
#ifdef O_PATH
  const int replaced = ::open(path.c_str(), O_PATH | O_NOFOLLOW | O_CLOEXEC);  // -1 when there is none
#else
  const int replaced = -1;
#endif
  const int err = std::rename(tmp.c_str(), path.c_str()) != 0 ? errno : 0;
  if (err) ::unlink(tmp.c_str());
  close_in_background(replaced);
  return err;
}

// Flushes the folder `dir` (its entries: the rename) to disk; returns errno on failure, 0 on
// success. Without it a crash soon after a save can bring the old file back under the name, the
// new one's data on disk but not the rename. EINVAL (a file system that cannot flush a folder)
// counts as success: there is nothing more to wait for there.
int sync_folder(const std::filesystem::path& dir) {
#ifdef O_DIRECTORY
  const int fd = ::open(dir.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (fd < 0) return errno;
  const int err = ::fsync(fd) != 0 && errno != EINVAL ? errno : 0;
  ::close(fd);
  return err;
#else
  (void)dir;
  return 0;
#endif
}

}  // namespace

void write_file_atomic(const std::string& path, const std::vector<unsigned char>& bytes) {
  write_file_atomic(path, std::vector<ByteSpan>{{bytes.data(), bytes.size()}});
}

void write_file_atomic(const std::string& path, const std::vector<ByteSpan>& bytes) {
  namespace fs = std::filesystem;
  const fs::path target(path);
  const fs::path dir = target.has_parent_path() ? target.parent_path() : fs::path(".");
  std::error_code ec;
  if (!fs::is_directory(dir, ec)) throw Error(ErrorCode::Io, path + ": folder " + dir.string() + " does not exist");
  std::random_device rd;
  const fs::path tmp = dir / ("." + target.filename().string() + ".tmp" + std::to_string(rd()));
  auto fail = [&](const std::string& what, int err) {
    throw Error(ErrorCode::Io, path + ": " + what + " (" + std::strerror(err) + ")");
  };
  // Renames the temporary over `path`, then flushes the folder so the rename outlasts a crash.
  auto replace = [&] {
    if (const int err = replace_file(tmp.string(), path)) fail("cannot replace the file", err);
    if (const int err = sync_folder(dir))  // the new content is in place: say so
      fail("saved, but the folder could not be flushed", err);
  };
#ifdef O_TMPFILE
  // Preferred: an unnamed temporary (O_TMPFILE). Until it is linked it has no name, so a writer
  // killed while writing (SIGKILL, power loss) leaves nothing behind; it gets its temporary name
  // only for the instant between the link and the rename.
  UniqueFd fd(::open(dir.c_str(), O_TMPFILE | O_RDWR | O_CLOEXEC, 0644));  // read too: mapped
  if (fd.get() >= 0) {
    if (const int err = write_unnamed_and_sync(fd.get(), bytes)) fail("write failed", err);
    const std::string self = "/proc/self/fd/" + std::to_string(fd.get());
    const bool linked = ::linkat(AT_FDCWD, self.c_str(), AT_FDCWD, tmp.c_str(), AT_SYMLINK_FOLLOW) == 0;
    if (const int err = fd.close()) {  // checked as the named temporary's close below is
      if (linked) ::unlink(tmp.c_str());
      fail("write failed", err);
    }
    if (linked) {
      replace();
      return;
    }
    // No /proc or no link support: fall back to a named temporary below.
  }
#endif
  const int named = ::open(tmp.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0644);
  if (named < 0) fail("cannot create a temporary file", errno);
  if (const int err = write_all_and_sync(named, bytes)) {
    ::close(named);
    ::unlink(tmp.c_str());
    fail("write failed", err);
  }
  if (::close(named) != 0) {
    const int err = errno;
    ::unlink(tmp.c_str());
    fail("write failed", err);
  }
  replace();
}

void force_fill_way(FillWay way) { forced_fill_way = static_cast<unsigned>(way); }

unsigned last_fill_ways() { return fill_ways.load(); }

bool has_extension(const std::string& path, const char* ext) {
  std::string e = std::filesystem::path(path).extension().string();
  std::transform(e.begin(), e.end(), e.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return e == ext;
}

}  // namespace deepcut::gltf_detail

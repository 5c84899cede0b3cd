// SPDX-License-Identifier: MIT
// Nothing lost (issue 10): a writer killed at any moment leaves the target either absent or the
// previous complete file, never a partial one, and never leaves a partial temporary behind.
#include <fcntl.h>
#include <gtest/gtest.h>
#include <linux/magic.h>
#include <signal.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <sys/vfs.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <random>
#include <string>
#include <thread>
#include <vector>

#include "deepcut/core/errors.h"
#include "deepcut/core/generate/cactus.h"
#include "deepcut/core/io/gltf.h"
#include "deepcut/core/parallel.h"
#include "io/gltf_common.h"
#include "thread_count.h"
#include "tools.h"

namespace deepcut {
namespace {

namespace fs = std::filesystem;

std::string read_bytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

// Writes `model` to `path` in a child process and SIGKILLs it after `delay` (if it is still
// running; a negative delay lets it finish). Returns true when the child finished the write.
bool write_and_kill(const Model& model, const std::string& path, std::chrono::microseconds delay) {
  const pid_t pid = ::fork();
  if (pid == 0) {
    try {
      write_gltf(model, path);
    } catch (...) {
      ::_exit(3);
    }
    ::_exit(0);
  }
  if (pid < 0) return false;
  if (delay.count() >= 0) {
    std::this_thread::sleep_for(delay);
    ::kill(pid, SIGKILL);
  }
  int status = 0;
  ::waitpid(pid, &status, 0);
  return WIFEXITED(status) && WEXITSTATUS(status) == 0;
}

// Files in `dir` other than the ones named.
std::vector<std::string> other_files(const std::string& dir, const std::vector<std::string>& known) {
  std::vector<std::string> out;
  for (const auto& e : fs::directory_iterator(dir)) {
    const std::string name = e.path().filename().string();
    if (std::find(known.begin(), known.end(), name) == known.end()) out.push_back(name);
  }
  return out;
}

bool supports_unnamed_temporaries(const std::string& dir) {
#ifdef O_TMPFILE
  const int fd = ::open(dir.c_str(), O_TMPFILE | O_WRONLY | O_CLOEXEC, 0644);
  if (fd < 0) return false;
  ::close(fd);
  return true;
#else
  (void)dir;
  return false;
#endif
}

TEST(AtomicWriteTest, a_writer_killed_at_random_moments_never_leaves_a_partial_file_or_a_temporary) {
  const std::string dir = test::temp_dir("atomic-write");
  const std::string target = dir + "/model.glb", reference = dir + "/reference.glb", old_file = dir + "/old.glb";
  CactusOptions small;
  small.target_triangles = 2000;
  write_gltf(make_cactus(small), old_file);
  CactusOptions large;
  large.target_triangles = 250000;
  const Model big = make_cactus(large);
  write_gltf(big, reference);
  // The child's own time for the whole write (fork and copy-on-write included), unkilled.
  const auto t0 = std::chrono::steady_clock::now();
  ASSERT_TRUE(write_and_kill(big, dir + "/timing.glb", std::chrono::microseconds(-1)));
  const auto full = std::chrono::duration_cast<std::chrono::microseconds>(std::chrono::steady_clock::now() - t0);
  fs::remove(dir + "/timing.glb");
  const std::string old_bytes = read_bytes(old_file), new_bytes = read_bytes(reference);
  ASSERT_GT(new_bytes.size(), 10u * 1000u * 1000u);
  const auto validation = test::run_command("node " + test::quote(DEEPCUT_VALIDATOR_SCRIPT) + " " +
                                            test::quote(old_file) + " " + test::quote(reference));
  ASSERT_EQ(validation.exit_code, 0) << validation.out << validation.err;

  // Kill moments spread over the whole write (and a little past it): serialising, writing the
  // temporary, flushing it and renaming it. The first run is killed at once, the last one is not
  // killed, so both outcomes occur whatever the machine's speed.
  constexpr int kKills = 30;
  const std::uint64_t seed = 20261122;
  std::mt19937_64 rng(seed);
  const bool unnamed = supports_unnamed_temporaries(dir);
  int kept_old = 0, absent = 0, completed = 0;
  for (int i = 0; i < kKills; ++i) {
    // Half of the runs start with an older complete file at the target, half with none.
    const bool with_old = i % 2 == 0;
    fs::remove(target);
    if (with_old) fs::copy_file(old_file, target);
    const auto delay = std::chrono::microseconds(
        i == 0 ? 0 : i == kKills - 1 ? -1 : std::uniform_int_distribution<long long>(0, full.count() * 12 / 10)(rng));
    const bool finished = write_and_kill(big, target, delay);
    const std::string what = "kill " + std::to_string(i) + " after " + std::to_string(delay.count()) +
                             " us (full write " + std::to_string(full.count()) + " us, seed " + std::to_string(seed) + ")";
    if (!fs::exists(target)) {
      EXPECT_FALSE(with_old) << what << ": the old file is gone";
      EXPECT_FALSE(finished) << what << ": the writer finished but wrote nothing";
      ++absent;
    } else {
      const std::string bytes = read_bytes(target);
      const bool is_old = with_old && bytes == old_bytes, is_new = bytes == new_bytes;
      EXPECT_TRUE(is_old || is_new) << what << ": the target is neither the old nor the new complete file ("
                                    << bytes.size() << " bytes)";
      if (finished) {
        EXPECT_TRUE(is_new) << what;
      }
      kept_old += is_old;
      completed += is_new;
    }
    // With unnamed temporaries (O_TMPFILE) the file only gets a name for the instant between
    // linking it (complete and flushed) and renaming it over the target: a kill in that instant
    // (seen under heavy load) may leave that name behind, but then it holds the complete new file;
    // a partial temporary is never left.
    const auto leftovers = other_files(dir, {"model.glb", "reference.glb", "old.glb"});
    if (unnamed) {
      EXPECT_LE(leftovers.size(), 1u) << what << ": left " << leftovers.size() << " temporaries";
      for (const auto& f : leftovers)
        EXPECT_EQ(read_bytes(dir + "/" + f), new_bytes) << what << ": left a partial temporary " << f;
    }
    for (const auto& f : leftovers) fs::remove(dir + "/" + f);
  }
  std::printf("[atomic] %d kills: %d kept the old file, %d left no file, %d completed (full write %lld us, O_TMPFILE %s)\n",
              kKills, kept_old, absent, completed, static_cast<long long>(full.count()), unnamed ? "yes" : "no");
  // The kills landed both before and after the rename, or the test proved nothing.
  EXPECT_GT(kept_old + absent, 0);
  EXPECT_GT(completed, 0);
  fs::remove_all(dir);
}

// Bytes 0..n-1 of a pattern that differs from part to part (`seed`), so a part written at the
// wrong place or twice shows.
std::vector<unsigned char> pattern(std::size_t n, std::uint32_t seed) {
  std::vector<unsigned char> out(n);
  std::uint32_t x = seed * 2654435761u + 1;
  for (std::size_t i = 0; i < n; ++i) {
    x = x * 1664525u + 1013904223u;
    out[i] = static_cast<unsigned char>(x >> 24);
  }
  return out;
}

// Writes spans of odd sizes to `dir`/out.bin on 1 and 3 threads and checks every byte, then
// writes it twice and checks that the second content won.
void check_spans(const std::string& dir) {
  const std::string target = dir + "/out.bin";
  constexpr std::size_t MiB = std::size_t(1) << 20;
  const std::vector<std::vector<std::size_t>> layouts = {
      {7 * MiB + 1, 20 * MiB, 5 * MiB - 3},  // crosses 16 MiB and 32 MiB inside spans
      {16 * MiB, 1, 16 * MiB - 1, 3},        // ends a part exactly, then a span of one byte
      {0, 33 * MiB + 5, 0},                  // empty spans around one over two parts
      {4 * MiB + 1},                         // two pieces, the second of one byte
      {1, 1, 8 * MiB - 2, 2},                // many spans inside the first piece, one past the second
      {8 * MiB},                             // whole pieces only, no partial block at the end
  };
  std::uint32_t seed = 1;
  for (const std::size_t t : {std::size_t(1), std::size_t(3)}) {
    const test::ThreadCount threads(t);
    for (const auto& sizes : layouts) {
      std::vector<std::vector<unsigned char>> spans;
      std::string expected;
      for (const std::size_t n : sizes) {
        spans.push_back(pattern(n, seed++));
        expected.append(spans.back().begin(), spans.back().end());
      }
      std::vector<gltf_detail::ByteSpan> parts;
      for (const auto& s : spans) parts.push_back({s.data(), s.size()});
      gltf_detail::write_file_atomic(target, parts);
      EXPECT_EQ(fs::file_size(target), expected.size());
      EXPECT_TRUE(read_bytes(target) == expected)
          << dir << ": layout starting " << sizes[0] << " bytes, " << t << " threads";
      EXPECT_TRUE(other_files(dir, {"out.bin"}).empty()) << "a temporary was left behind";
    }
  }
  // Written twice to the same path, the second content is what the file holds.
  const std::vector<unsigned char> first = pattern(17 * MiB + 7, 100), second = pattern(3 * MiB + 11, 200);
  gltf_detail::write_file_atomic(target, first);
  gltf_detail::write_file_atomic(target, second);
  EXPECT_TRUE(read_bytes(target) == std::string(second.begin(), second.end())) << dir;
  EXPECT_TRUE(other_files(dir, {"out.bin"}).empty()) << "a temporary was left behind";
}

// One thread writes the file in 16 MiB parts (each handed to the disk as it is complete); several
// write 4 MiB pieces in parallel, straight to the disk where the file system takes direct writes
// and through mappings of the file elsewhere (tmpfs, /dev/shm when there is one). Spans of odd
// sizes cross those parts and pieces at odd places, and every byte still lands where it belongs.
TEST(AtomicWriteTest, spans_of_odd_sizes_crossing_the_write_parts_are_written_whole_and_the_last_write_wins) {
  const std::string dir = test::temp_dir("atomic-spans");
  check_spans(dir);
  fs::remove_all(dir);
  std::error_code ec;
  if (fs::is_directory("/dev/shm", ec)) {
    const std::string shm = "/dev/shm/deepcut-atomic-spans-" + std::to_string(::getpid());
    if (fs::create_directory(shm, ec)) {
      check_spans(shm);
      fs::remove_all(shm, ec);
    }
  }
}

TEST(AtomicWriteTest, a_write_into_a_read_only_folder_fails_with_an_error_naming_the_path) {
  if (::geteuid() == 0) GTEST_SKIP() << "running as root: folder permissions do not apply";
  const std::string dir = test::temp_dir("atomic-read-only");
  const std::string target = dir + "/out.bin";
  ASSERT_EQ(::chmod(dir.c_str(), 0555), 0);
  bool threw = false;
  try {
    gltf_detail::write_file_atomic(target, pattern(1000, 7));
  } catch (const Error& e) {
    threw = true;
    EXPECT_EQ(e.code(), ErrorCode::Io);
    EXPECT_NE(std::string(e.what()).find(target), std::string::npos) << e.what();
  }
  EXPECT_TRUE(threw) << "no Error for a read-only folder";
  EXPECT_FALSE(fs::exists(target));
  ::chmod(dir.c_str(), 0755);
  EXPECT_TRUE(other_files(dir, {}).empty()) << "a temporary was left behind";
  fs::remove_all(dir);
}

// Forces one way of filling the unnamed temporary for a scope (the test seam), then Auto again.
class ForcedFillWay {
 public:
  explicit ForcedFillWay(gltf_detail::FillWay way) { gltf_detail::force_fill_way(way); }
  ~ForcedFillWay() { gltf_detail::force_fill_way(gltf_detail::FillWay::Auto); }
  ForcedFillWay(const ForcedFillWay&) = delete;
  ForcedFillWay& operator=(const ForcedFillWay&) = delete;
};

// Whether a regular file in `dir` takes direct writes the parallel write can use (STATX_DIOALIGN
// reported, and a block 4 MiB is a multiple of).
bool takes_direct_writes(const std::string& dir) {
#if defined(STATX_DIOALIGN) && defined(O_DIRECT)
  const std::string probe = dir + "/probe";
  { std::ofstream(probe) << "x"; }
  struct statx sx {};
  const bool ok = ::statx(AT_FDCWD, probe.c_str(), 0, STATX_DIOALIGN, &sx) == 0 &&
                  (sx.stx_mask & STATX_DIOALIGN) && sx.stx_dio_offset_align != 0 &&
                  sx.stx_dio_mem_align != 0 && (std::size_t(4) << 20) % sx.stx_blksize == 0;
  fs::remove(probe);
  return ok;
#else
  (void)dir;
  return false;
#endif
}
// Whether `dir`'s file system keeps reserved blocks (ext4, xfs, tmpfs: the pieces are mapped there).
bool keeps_reserved_blocks(const std::string& dir) {
  struct statfs sf {};
  if (::statfs(dir.c_str(), &sf) != 0) return false;
  const auto type = static_cast<unsigned long>(sf.f_type);
  return type == EXT4_SUPER_MAGIC || type == XFS_SUPER_MAGIC || type == TMPFS_MAGIC;
}

// Each way of filling the temporary (forced through the test seam) writes the same bytes, and is
// the way that ran: straight to the disk, through mappings, with pwrite, or in one stream.
TEST(AtomicWriteTest, each_way_of_filling_the_temporary_is_the_one_taken_and_writes_the_same_bytes) {
  using gltf_detail::FillWay;
  const std::string dir = test::temp_dir("atomic-ways");
  const std::string target = dir + "/out.bin";
  constexpr std::size_t MiB = std::size_t(1) << 20;
  const test::ThreadCount threads(3);
  // Three pieces, spans crossing them at odd places, the last block partial.
  std::vector<std::vector<unsigned char>> spans = {pattern(1, 1), pattern(5 * MiB - 7, 2),
                                                   pattern(3 * MiB + 13, 3), pattern(2 * MiB + 1, 4)};
  std::string expected;
  std::vector<gltf_detail::ByteSpan> parts;
  for (const auto& s : spans) {
    expected.append(s.begin(), s.end());
    parts.push_back({s.data(), s.size()});
  }
  const bool direct = takes_direct_writes(dir), mapped = keeps_reserved_blocks(dir);
  const unsigned tail = mapped ? unsigned(FillWay::Mapped) : unsigned(FillWay::Pwrite);  // the partial block
  const unsigned auto_ways = direct ? unsigned(FillWay::Direct) | tail : tail;
  const std::pair<FillWay, unsigned> cases[] = {{FillWay::Auto, auto_ways},
                                                {FillWay::Direct, auto_ways},
                                                {FillWay::Mapped, unsigned(FillWay::Mapped)},
                                                {FillWay::Pwrite, unsigned(FillWay::Pwrite)},
                                                {FillWay::Plain, unsigned(FillWay::Plain)}};
  for (const auto& [way, ways] : cases) {
    std::remove(target.c_str());
    {
      const ForcedFillWay forced(way);
      gltf_detail::write_file_atomic(target, parts);
    }
    EXPECT_EQ(gltf_detail::last_fill_ways(), ways) << "forced " << unsigned(way) << " on " << dir;
    EXPECT_EQ(fs::file_size(target), expected.size());
    EXPECT_TRUE(read_bytes(target) == expected) << "forced " << unsigned(way);
    EXPECT_TRUE(other_files(dir, {"out.bin"}).empty()) << "a temporary was left behind";
  }
  std::printf("[atomic] %s: direct writes %s, mapped %s\n", dir.c_str(), direct ? "yes" : "no",
              mapped ? "yes" : "no");
  fs::remove_all(dir);
}

// The descriptors this process has open.
std::size_t open_descriptors() {
  std::size_t n = 0;
  for ([[maybe_unused]] const auto& entry : fs::directory_iterator("/proc/self/fd")) ++n;
  return n;
}

// The file size limit (RLIMIT_FSIZE) set to `bytes` for a scope, SIGXFSZ ignored so that going
// past it is an EFBIG error, not the end of the process; both restored after.
class FileSizeLimit {
 public:
  explicit FileSizeLimit(rlim_t bytes) {
    ::getrlimit(RLIMIT_FSIZE, &saved_);
    old_handler_ = ::signal(SIGXFSZ, SIG_IGN);
    struct rlimit limit = saved_;
    limit.rlim_cur = bytes;
    set_ = ::setrlimit(RLIMIT_FSIZE, &limit) == 0;
  }
  ~FileSizeLimit() {
    ::setrlimit(RLIMIT_FSIZE, &saved_);
    ::signal(SIGXFSZ, old_handler_);
  }
  FileSizeLimit(const FileSizeLimit&) = delete;
  FileSizeLimit& operator=(const FileSizeLimit&) = delete;
  bool set() const { return set_; }

 private:
  struct rlimit saved_ {};
  sighandler_t old_handler_ = SIG_DFL;
  bool set_ = false;
};

// A write the file system refuses partway (EFBIG past the file size limit, as a full disk would
// be) fails with an Error naming the path; the old file stays, and no temporary or descriptor
// is left behind.
TEST(AtomicWriteTest,
     a_parallel_write_past_the_file_size_limit_fails_naming_the_path_and_leaves_the_old_file) {
  const std::string dir = test::temp_dir("atomic-efbig");
  const std::string target = dir + "/out.bin";
  constexpr std::size_t MiB = std::size_t(1) << 20;
  const test::ThreadCount threads(3);
  const std::vector<unsigned char> old = pattern(1000, 7), big = pattern(8 * MiB, 8);
  gltf_detail::write_file_atomic(target, old);
  const std::size_t descriptors = open_descriptors();
  bool threw = false;
  {
    const FileSizeLimit limit(6 * MiB);
    ASSERT_TRUE(limit.set());
    try {
      gltf_detail::write_file_atomic(target, big);
    } catch (const Error& e) {
      threw = true;
      EXPECT_EQ(e.code(), ErrorCode::Io);
      EXPECT_NE(std::string(e.what()).find(target), std::string::npos) << e.what();
    }
  }
  EXPECT_TRUE(threw) << "no Error for a write past the file size limit";
  EXPECT_TRUE(read_bytes(target) == std::string(old.begin(), old.end())) << "the old file was not kept";
  EXPECT_TRUE(other_files(dir, {"out.bin"}).empty()) << "a temporary was left behind";
  EXPECT_EQ(open_descriptors(), descriptors) << "a descriptor was left open";
  fs::remove_all(dir);
}

}  // namespace
}  // namespace deepcut

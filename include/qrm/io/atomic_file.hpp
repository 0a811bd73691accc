// qrm/io/atomic_file.hpp: whole-file writes that never leave a half-written output.
//
// write_file_atomically(target, writer) creates the missing parent directories, writes into a
// fresh temporary file in the target's own directory (".<name>.<pid>.<counter>.tmp", opened
// exclusively), flushes it, fsyncs it (POSIX), and renames it over the target. A reader of
// `target` therefore sees the old content or the new content, never a mixture. On any failure
// the temporary file is removed and the error propagates: our own I/O failures throw
// std::runtime_error naming the path and the reason (the errno text); an exception thrown by the
// writer callback is rethrown unchanged after the clean-up. (On POSIX, rename replaces an
// existing target atomically; other systems are not supported by this header's guarantees.)
//
// Signals: remove_temporary_files_on_signals() (called once by a program, e.g. the qrm tool)
// makes SIGINT, SIGTERM and SIGHUP remove every temporary file still being written and exit
// with 128 + the signal number (130, 143, 129), so an interrupted run leaves no ".tmp" files.
// Temporary files are registered in a fixed table (64 at a time, paths up to 4095 bytes) that
// the handler reads with async-signal-safe calls only.
#pragma once

#include <atomic>
#include <cerrno>
#include <concepts>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <stdexcept>
#include <string>
#include <string_view>
#include <system_error>
#include <utility>

#if defined(__unix__) || defined(__APPLE__)
#include <fcntl.h>
#include <signal.h>
#include <unistd.h>
#define QRM_IO_POSIX 1
#else
#define QRM_IO_POSIX 0
#endif

namespace qrm::detail {

inline std::string errno_text(int err) { return std::error_code(err, std::generic_category()).message(); }

// One counter per process: with the pid it makes temporary names unique across threads and
// processes writing into the same directory.
inline std::atomic<std::uint64_t> temp_file_counter{0};

template <int = 0>
inline unsigned long process_id() {
#if QRM_IO_POSIX
  return static_cast<unsigned long>(::getpid());
#else
  return 0;
#endif
}

// Best effort: makes the rename itself durable. Some file systems refuse fsync on directories;
// the content is already safe at that point, so failures are ignored.
template <int = 0>
inline void sync_directory(const std::filesystem::path& dir) {
#if QRM_IO_POSIX
  const std::string d = dir.empty() ? std::string(".") : dir.string();
  const int fd = ::open(d.c_str(), O_RDONLY);
  if (fd >= 0) {
    (void)::fsync(fd);
    (void)::close(fd);
  }
#else
  (void)dir;
#endif
}

// The temporary files being written, for the signal handler. A slot is claimed with an atomic
// exchange, filled, then published; the handler reads only published slots.
struct temp_file_slot {
  std::atomic<int> state{0};  // 0 free, 1 being filled or cleared, 2 published
  char path[4096] = {};
};
inline temp_file_slot temp_file_slots[64];

// Registers `path`; returns the slot, or -1 when the table is full or the path too long (the file
// is then still removed on every error, only not on a signal).
template <int = 0>
inline int register_temp_file(const std::string& path) {
  if (path.size() >= sizeof temp_file_slots[0].path) return -1;
  for (int i = 0; i < 64; ++i) {
    int expected = 0;
    if (!temp_file_slots[i].state.compare_exchange_strong(expected, 1)) continue;
    path.copy(temp_file_slots[i].path, path.size());
    temp_file_slots[i].path[path.size()] = '\0';
    temp_file_slots[i].state.store(2, std::memory_order_release);
    return i;
  }
  return -1;
}

template <int = 0>
inline void unregister_temp_file(int slot) {
  if (slot >= 0) temp_file_slots[slot].state.store(0, std::memory_order_release);
}

// Async-signal-safe: unlink every published temporary file.
template <int = 0>
inline void remove_registered_temp_files() {
#if QRM_IO_POSIX
  for (temp_file_slot& s : temp_file_slots)
    if (s.state.load(std::memory_order_acquire) == 2) (void)::unlink(s.path);
#endif
}

#if QRM_IO_POSIX
// Blocks SIGINT, SIGTERM and SIGHUP for the calling thread while it lives.
class signals_blocked {
 public:
  signals_blocked() {
    sigset_t set;
    sigemptyset(&set);
    for (int sig : {SIGINT, SIGTERM, SIGHUP}) sigaddset(&set, sig);
    (void)::pthread_sigmask(SIG_BLOCK, &set, &old_);
  }
  ~signals_blocked() { (void)::pthread_sigmask(SIG_SETMASK, &old_, nullptr); }
  signals_blocked(const signals_blocked&) = delete;
  signals_blocked& operator=(const signals_blocked&) = delete;

 private:
  sigset_t old_;
};

template <int = 0>
inline void remove_temp_files_and_exit(int sig) {
  remove_registered_temp_files();
  ::_exit(128 + sig);
}
#else
struct signals_blocked {};
#endif

}  // namespace qrm::detail

namespace qrm::io {

// remove_temporary_files_on_signals(): SIGINT, SIGTERM and SIGHUP remove the temporary files of
// writes in flight and exit with 128 + the signal (see the header comment). POSIX only; a no-op
// elsewhere.
template <int = 0>
inline void remove_temporary_files_on_signals() {
#if QRM_IO_POSIX
  struct sigaction sa {};
  sa.sa_handler = detail::remove_temp_files_and_exit;
  sigemptyset(&sa.sa_mask);
  for (int sig : {SIGINT, SIGTERM, SIGHUP}) (void)::sigaction(sig, &sa, nullptr);
#endif
}

// file_sink: what a writer callback writes into. Every failed write throws std::runtime_error
// naming the file being written and the errno text.
class file_sink {
 public:
  template <int = 0>
  file_sink(std::FILE* f, std::filesystem::path target) : f_(f), target_(std::move(target)) {}
  file_sink(const file_sink&) = delete;
  file_sink& operator=(const file_sink&) = delete;

  // write(data, n): appends n bytes.
  template <int = 0>
  void write(const void* data, std::size_t n) {
    if (n == 0) return;
    errno = 0;
    if (std::fwrite(data, 1, n, f_) != n) fail("write");
    written_ += n;
  }
  // write(text): appends the bytes of `text`.
  void write(std::string_view text) { write(text.data(), text.size()); }
  // put(byte): appends one byte.
  void put(unsigned char byte) { write(&byte, 1); }
  // bytes_written(): total bytes appended so far.
  std::uint64_t bytes_written() const { return written_; }

 private:
  [[noreturn]] void fail(const char* what) const {
    const int err = errno;
    throw std::runtime_error("cannot " + std::string(what) + " '" + target_.string() +
                             "': " + (err != 0 ? detail::errno_text(err) : std::string("I/O error")));
  }
  std::FILE* f_;
  std::filesystem::path target_;
  std::uint64_t written_ = 0;
};

// ensure_directory(dir): creates `dir` and its parents if missing; throws std::runtime_error
// naming the directory and the reason (e.g. a component is a file). Commands call it before
// they compute anything, so a bad output path fails at once rather than after the work.
template <int = 0>
inline void ensure_directory(const std::filesystem::path& dir, const std::string& purpose = {}) {
  if (dir.empty()) return;
  std::error_code ec;
  if (std::filesystem::is_directory(dir, ec)) return;
  std::filesystem::create_directories(dir, ec);
  if (ec || !std::filesystem::is_directory(dir))
    throw std::runtime_error("cannot create directory '" + dir.string() + "'" + purpose + ": " +
                             (ec ? ec.message() : std::string("a path component is not a directory")));
}

// ensure_parent_directory(target): ensure_directory of the directory that will hold `target`.
template <int = 0>
inline void ensure_parent_directory(const std::filesystem::path& target) {
  ensure_directory(target.parent_path(), " for '" + target.string() + "'");
}

// write_file_atomically(target, writer): calls writer(file_sink&) to produce the whole content of
// `target`, then replaces `target` with it in one rename. See the header comment for guarantees.
template <std::invocable<file_sink&> Writer>
void write_file_atomically(const std::filesystem::path& target, Writer&& writer) {
  if (target.empty()) throw std::invalid_argument("write_file_atomically: the target path is empty");
  if (!target.has_filename())
    throw std::invalid_argument("write_file_atomically: '" + target.string() + "' does not name a file");
  ensure_parent_directory(target);

  const std::filesystem::path dir = target.parent_path();
  std::filesystem::path temp;
  std::FILE* f = nullptr;
  int slot = -1;
  {
    // Signals wait while the file is created and registered, so none can leave it behind.
    const detail::signals_blocked quiet;
    // "x" (C11, exclusive create) refuses an existing file, so a stale temporary file from a
    // crashed process is never reused or clobbered; a collision just takes the next counter.
    for (int attempt = 0; attempt < 100 && f == nullptr; ++attempt) {
      const std::uint64_t n = detail::temp_file_counter.fetch_add(1);
      std::string name = ".";
      name.append(target.filename().string()).append(".").append(std::to_string(detail::process_id()));
      name.append(".").append(std::to_string(n)).append(".tmp");
      temp = dir / name;
      errno = 0;
      f = std::fopen(temp.string().c_str(), "wbx");
      if (f == nullptr && errno != EEXIST) break;
    }
    if (f != nullptr) slot = detail::register_temp_file(temp.string());
  }
  if (f == nullptr) {
    const int err = errno;
    throw std::runtime_error("cannot create temporary file '" + temp.string() + "' for '" + target.string() +
                             "': " + detail::errno_text(err));
  }
  // Unregistered after the rename or the removal; a signal in between unlinks a name that is gone.
  struct registration {
    int slot;
    ~registration() { detail::unregister_temp_file(slot); }
  } registered{slot};

  auto fail = [&](const std::string& what, int err) {
    if (f != nullptr) std::fclose(f);
    f = nullptr;
    std::remove(temp.string().c_str());
    throw std::runtime_error("cannot write '" + target.string() + "' (" + what + "): " +
                             (err != 0 ? detail::errno_text(err) : std::string("I/O error")));
  };

  try {
    file_sink sink(f, target);
    std::forward<Writer>(writer)(sink);
  } catch (...) {
    std::fclose(f);
    std::remove(temp.string().c_str());
    throw;
  }
  errno = 0;
  if (std::fflush(f) != 0) fail("flush", errno);
#if QRM_IO_POSIX
  errno = 0;
  if (::fsync(::fileno(f)) != 0) fail("fsync", errno);
#endif
  errno = 0;
  const int closed = std::fclose(f);
  f = nullptr;
  if (closed != 0) fail("close", errno);
  errno = 0;
  if (std::rename(temp.string().c_str(), target.string().c_str()) != 0)
    fail("rename from '" + temp.string() + "'", errno);
  detail::sync_directory(dir);
}

// write_file_atomically(target, contents): the same, for content already in memory.
template <int = 0>
void write_file_atomically(const std::filesystem::path& target, std::string_view contents) {
  write_file_atomically(target, [contents](file_sink& out) { out.write(contents); });
}

}  // namespace qrm::io

// This header's part of <qrm/io/compiled_io.hpp> (QRM_COMPILED_IO).
#define QRM_DETAIL_ATOMIC_FILE_INSTANCES(PREFIX)                                        \
  PREFIX void write_file_atomically<0>(const std::filesystem::path&, std::string_view);
#ifdef QRM_COMPILED_IO
namespace qrm::io {
QRM_DETAIL_ATOMIC_FILE_INSTANCES(extern template)
}  // namespace qrm::io
#endif

#include "shellflow/core/output_file.h"

#include <fcntl.h>
#include <spdlog/spdlog.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <sstream>
#include <utility>
#include <vector>

#include "shellflow/core/error.h"

namespace shellflow {

namespace fs = std::filesystem;

namespace {

bool write_all(int fd, std::string_view bytes) {
  while (!bytes.empty()) {
    const ssize_t n = ::write(fd, bytes.data(), bytes.size());
    if (n < 0) {
      if (errno == EINTR) continue;
      return false;
    }
    bytes.remove_prefix(std::size_t(n));
  }
  return true;
}

/// The Error for a failed open of `path` for writing: a link gets link_refusal.
[[noreturn]] void throw_open_error(const fs::path& path, int err) {
  if (err == ELOOP || err == EMLINK) throw Error(link_refusal(path));
  throw Error(fmt::format("{}: cannot open it for writing ({})", printable(path.string()), std::strerror(err)));
}

/// Refuses an open descriptor that is not a regular file of its own: another name for the
/// same inode (a hard link) would have us cut or overwrite a file outside the output folder.
void check_own_regular_file(int fd, const fs::path& path) {
  struct stat st {};
  std::string why;
  if (::fstat(fd, &st) != 0)
    why = fmt::format("cannot read its status ({})", std::strerror(errno));
  else if (!S_ISREG(st.st_mode))
    why = "not a regular file";
  else if (st.st_nlink > 1)
    why = fmt::format("is a hard link ({} names for one file); shellflow does not write through links", st.st_nlink);
  if (why.empty()) return;
  ::close(fd);
  throw Error(fmt::format("{}: {}; remove it, or choose another folder with -o", printable(path.string()), why));
}

void create_parent(const fs::path& path) {
  if (!path.has_parent_path()) return;
  std::error_code ec;
  fs::create_directories(path.parent_path(), ec);
  if (ec)
    throw Error(fmt::format("cannot create directory {} for {}: {}", printable(path.parent_path().string()),
                            printable(path.string()), ec.message()));
}

bool g_writes_files = true;

void write_parts_atomically(const fs::path& path, const std::vector<std::string_view>& parts, bool sync) {
  if (!g_writes_files) return;
  create_parent(path);
  std::error_code ec;
  if (fs::is_directory(fs::symlink_status(path, ec)))
    throw Error(fmt::format("{}: is a folder; cannot write the file of that name there", printable(path.string())));
  fs::path tmp = path;
  tmp += ".tmp";
  // A leftover (or a planted link) of that name goes first: the temporary is always new.
  if (::unlink(tmp.c_str()) != 0 && errno != ENOENT)
    throw Error(fmt::format("{}: cannot remove the old temporary ({})", printable(tmp.string()), std::strerror(errno)));
  const int fd = ::open(tmp.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_NOFOLLOW | O_CLOEXEC, 0644);
  if (fd < 0) throw_open_error(tmp, errno);
  bool ok = true;
  for (const std::string_view part : parts) ok = ok && write_all(fd, part);
  if (ok && sync) ok = ::fsync(fd) == 0;
  const int saved = errno;
  ok = (::close(fd) == 0) && ok;
  if (!ok) {
    ::unlink(tmp.c_str());
    throw Error(fmt::format("cannot write {} (disk full?): {}", printable(tmp.string()), std::strerror(saved)));
  }
  rename_into_place(tmp, path);
}

}  // namespace

std::string link_refusal(const fs::path& path) {
  std::error_code ec;
  const fs::path target = fs::read_symlink(path, ec);
  return fmt::format(
      "{}: is a symbolic link{}; shellflow does not write through links in an output folder: remove it, or choose "
      "another folder with -o",
      printable(path.string()), ec ? "" : fmt::format(" (to {})", printable(target.string())));
}

void write_file_atomically(const fs::path& path, const std::function<void(std::ostream&)>& fill) {
  std::ostringstream os;
  fill(os);
  const std::string bytes = std::move(os).str();
  write_parts_atomically(path, {bytes}, false);
}

void write_file_atomically(const fs::path& path, std::string_view bytes) {
  write_parts_atomically(path, {bytes}, false);
}

void write_file_atomically_synced(const fs::path& path, const std::vector<std::string_view>& parts) {
  write_parts_atomically(path, parts, true);
}

void rename_into_place(const fs::path& from, const fs::path& to) {
  if (::rename(from.c_str(), to.c_str()) != 0) {
    const int err = errno;
    ::unlink(from.c_str());
    throw Error(fmt::format("cannot rename {} to {}: {}", printable(from.string()), printable(to.string()),
                            std::strerror(err)));
  }
}

// ---- AppendFile -------------------------------------------------------------------------

bool process_writes_files() { return g_writes_files; }
void set_process_writes_files(bool writes) { g_writes_files = writes; }
PieceOutput::PieceOutput() : before_(std::exchange(g_writes_files, true)) {}
PieceOutput::~PieceOutput() { g_writes_files = before_; }

AppendFile::AppendFile(const fs::path& path, Mode mode) : path_(path) {
  if (!g_writes_files) {
    discard_ = true;
    return;
  }
  if (mode == Mode::truncate) create_parent(path);
  // Truncated only once it is known to be a file of its own (not through a hard link).
  const int flags = O_RDWR | O_APPEND | O_NOFOLLOW | O_CLOEXEC | (mode == Mode::truncate ? O_CREAT : 0);
  const int fd = ::open(path.c_str(), flags, 0644);
  if (fd < 0) throw_open_error(path, errno);
  check_own_regular_file(fd, path);
  if (mode == Mode::truncate && ::ftruncate(fd, 0) != 0) {
    const int err = errno;
    ::close(fd);
    throw Error(fmt::format("{}: cannot empty it ({})", printable(path.string()), std::strerror(err)));
  }
  fd_ = fd;
}

AppendFile::AppendFile(AppendFile&& o) noexcept
    : fd_(std::exchange(o.fd_, -1)), discard_(std::exchange(o.discard_, false)), path_(std::move(o.path_)) {}

AppendFile& AppendFile::operator=(AppendFile&& o) noexcept {
  if (this != &o) {
    if (fd_ >= 0) ::close(fd_);
    fd_ = std::exchange(o.fd_, -1);
    discard_ = std::exchange(o.discard_, false);
    path_ = std::move(o.path_);
  }
  return *this;
}

AppendFile::~AppendFile() {
  if (fd_ >= 0) ::close(fd_);
}

void AppendFile::write(std::string_view bytes) {
  if (discard_) return;
  if (fd_ < 0) throw Error(fmt::format("{}: not open", printable(path_.string())));
  struct stat st {};
  const bool sized = ::fstat(fd_, &st) == 0;
  if (write_all(fd_, bytes)) return;
  const int err = errno;
  // A part of a row (a full disk, a file size limit) is cut back: the file ends with a whole row.
  if (sized && ::ftruncate(fd_, st.st_size) != 0) {
  }
  throw Error(fmt::format("cannot write {} (disk full?): {}", printable(path_.string()), std::strerror(err)));
}

std::uint64_t AppendFile::size() const {
  struct stat st {};
  if (fd_ < 0 || ::fstat(fd_, &st) != 0)
    throw Error(fmt::format("{}: cannot read its size ({})", printable(path_.string()), std::strerror(errno)));
  return std::uint64_t(st.st_size);
}

std::string AppendFile::read_at(std::uint64_t offset, std::size_t n) const {
  std::string out(n, '\0');
  std::size_t got = 0;
  while (fd_ >= 0 && got < n) {
    const ssize_t r = ::pread(fd_, out.data() + got, n - got, off_t(offset + got));
    if (r < 0 && errno == EINTR) continue;
    if (r <= 0) break;
    got += std::size_t(r);
  }
  out.resize(got);
  return out;
}

void AppendFile::truncate(std::uint64_t size) {
  if (discard_) return;
  if (fd_ < 0 || ::ftruncate(fd_, off_t(size)) != 0)
    throw Error(
        fmt::format("{}: cannot cut it back to {} bytes ({})", printable(path_.string()), size, std::strerror(errno)));
}

// ---- temporaries for other writers ------------------------------------------------------

fs::path private_temporary(const fs::path& dir, const std::string& stem, const std::string& extension) {
  std::string name = (dir / (stem + ".XXXXXX" + extension)).string();
  std::vector<char> buffer(name.begin(), name.end());
  buffer.push_back('\0');
  const int fd = ::mkstemps(buffer.data(), int(extension.size()));  // O_CREAT | O_EXCL, mode 0600
  if (fd < 0)
    throw Error(
        fmt::format("{}: cannot create a temporary file there ({})", printable(dir.string()), std::strerror(errno)));
  ::fchmod(fd, 0644);
  ::close(fd);
  return fs::path(buffer.data());
}

// ---- OutputLock -------------------------------------------------------------------------

OutputLock::OutputLock(const fs::path& dir) {
  const fs::path file = dir / kFileName;
  const int fd = ::open(file.c_str(), O_RDWR | O_CREAT | O_NOFOLLOW | O_CLOEXEC, 0644);
  if (fd < 0) throw_open_error(file, errno);
  check_own_regular_file(fd, file);  // the pid written below would truncate a hard link's file
  fd_ = fd;
  if (::flock(fd_, LOCK_EX | LOCK_NB) != 0) {
    const int err = errno;
    if (err == ENOLCK || err == EOPNOTSUPP || err == ENOSYS) {
      // A file system without locks (some network mounts): the run goes on, unguarded.
      spdlog::warn(
          "{}: the file system does not lock files ({}); nothing keeps a second shellflow process out of "
          "this output folder",
          printable(dir.string()), std::strerror(err));
      return;
    }
    std::string pid(32, '\0');
    const ssize_t n = ::pread(fd_, pid.data(), pid.size(), 0);
    pid.resize(n > 0 ? std::size_t(n) : 0);
    while (!pid.empty() && (pid.back() == '\n' || pid.back() == ' ')) pid.pop_back();
    ::close(fd_);
    fd_ = -1;
    if (err == EWOULDBLOCK)
      throw Error(
          fmt::format("{}: another shellflow process{} is writing in this output folder; wait for it to end, or choose "
                      "another folder with -o",
                      printable(dir.string()), pid.empty() ? "" : fmt::format(" (pid {})", printable(pid))));
    throw Error(fmt::format("{}: cannot lock the output folder ({})", printable(file.string()), std::strerror(err)));
  }
  const std::string pid = fmt::format("{}\n", ::getpid());
  if (::ftruncate(fd_, 0) != 0 || ::pwrite(fd_, pid.data(), pid.size(), 0) != ssize_t(pid.size())) {
    // The lock holds without the pid; only the message of a second process lacks it.
  }
}

OutputLock::OutputLock(OutputLock&& o) noexcept : fd_(std::exchange(o.fd_, -1)) {}

OutputLock& OutputLock::operator=(OutputLock&& o) noexcept {
  if (this != &o) {
    if (fd_ >= 0) ::close(fd_);
    fd_ = std::exchange(o.fd_, -1);
  }
  return *this;
}

OutputLock::~OutputLock() {
  if (fd_ < 0) return;
  // Empty when nobody holds it (a killed holder leaves its pid); the lock goes with the
  // descriptor, the file stays.
  if (::ftruncate(fd_, 0) != 0) {
  }
  ::close(fd_);
}

}  // namespace shellflow

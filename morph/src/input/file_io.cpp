// SPDX-License-Identifier: Apache-2.0
// Whole-file reading and writing with every failure named (see file_io.h for the contract).
#include <fcntl.h>
#include <morph/exceptions.h>
#include <morph/file_io.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <climits>
#include <cstdlib>
#include <cstring>
#include <string>

namespace morph {

namespace {

std::string reason() {
  return std::strerror(errno);
}

/// What a file that is not a regular file is, for the refusal.
std::string kind_of(mode_t mode) {
  if (S_ISDIR(mode)) return "a directory";
  if (S_ISFIFO(mode)) return "a FIFO (named pipe)";
  if (S_ISCHR(mode)) return "a character device";
  if (S_ISBLK(mode)) return "a block device";
  if (S_ISSOCK(mode)) return "a socket";
  return "not a regular file";
}

std::string mebibytes(std::uint64_t bytes) {
  return std::to_string((bytes + (1 << 20) - 1) >> 20) + " MiB";
}

/// Closes a descriptor on every path out of a scope.
class Descriptor {
 public:
  explicit Descriptor(int fd) : fd_(fd) {}
  ~Descriptor() {
    if (fd_ >= 0) ::close(fd_);
  }
  Descriptor(const Descriptor&) = delete;
  Descriptor& operator=(const Descriptor&) = delete;
  int get() const { return fd_; }
  /// Closes now and reports close()'s error (where NFS and others report a failed write).
  int close() {
    const int result = ::close(fd_);
    fd_ = -1;
    return result;
  }

 private:
  int fd_;
};

/// Writes every byte or throws: a short write is retried, an error (ENOSPC, EIO) is reported.
void write_all(int fd, std::string_view bytes, const std::string& path) {
  std::size_t done = 0;
  while (done < bytes.size()) {
    const std::size_t chunk = std::min<std::size_t>(bytes.size() - done, std::size_t(1) << 30);
    const ssize_t n = ::write(fd, bytes.data() + done, chunk);
    if (n < 0) {
      if (errno == EINTR) continue;
      throw IoError(path + ": cannot write (" + reason() + ") after " + std::to_string(done) + " of " +
                    std::to_string(bytes.size()) + " bytes");
    }
    if (n == 0) throw IoError(path + ": cannot write (no progress after " + std::to_string(done) + " bytes)");
    done += std::size_t(n);
  }
}

std::string directory_of(const std::string& path) {
  const std::size_t slash = path.find_last_of('/');
  if (slash == std::string::npos) return ".";
  if (slash == 0) return "/";
  return path.substr(0, slash);
}

}  // namespace

std::string read_regular_file(const std::string& path, std::string_view what, std::uint64_t max_bytes) {
  const std::string role(what);
  // O_NONBLOCK: opening a FIFO without a writer returns at once instead of waiting for one; the
  // descriptor is then refused below, before any read.
  Descriptor fd(::open(path.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC | O_NOCTTY));
  if (fd.get() < 0) throw IoError(path + ": cannot open " + role + " (" + reason() + ")");
  struct stat st {};
  if (::fstat(fd.get(), &st) != 0) throw IoError(path + ": cannot open " + role + " (" + reason() + ")");
  if (!S_ISREG(st.st_mode))
    throw InputError(path + ": the " + role + " is " + kind_of(st.st_mode) +
                     ", not a regular file; MorphMill reads inputs only from regular files");
  const std::uint64_t size = std::uint64_t(st.st_size);
  if (size > max_bytes)
    throw InputError(path + ": the " + role + " is " + mebibytes(size) + ", over the limit of " +
                     mebibytes(max_bytes) + " for one input file");
  std::string data(std::size_t(size), '\0');
  std::size_t done = 0;
  while (true) {
    if (done == data.size()) {
      // The file may have grown since fstat: read on, within the cap, until the end.
      if (data.size() >= max_bytes) {
        char probe;
        const ssize_t n = ::read(fd.get(), &probe, 1);
        if (n == 0) break;
        if (n < 0 && errno == EINTR) continue;
        if (n < 0) throw IoError(path + ": cannot read " + role + " (" + reason() + ")");
        throw InputError(path + ": the " + role + " grew past the limit of " + mebibytes(max_bytes) +
                         " while it was read");
      }
      data.resize(std::size_t(std::min<std::uint64_t>(max_bytes, std::uint64_t(data.size()) + 65536)));
    }
    const ssize_t n = ::read(fd.get(), data.data() + done, data.size() - done);
    if (n < 0) {
      if (errno == EINTR) continue;
      throw IoError(path + ": cannot read " + role + " (" + reason() + ")");
    }
    if (n == 0) break;
    done += std::size_t(n);
  }
  data.resize(done);
  return data;
}

void write_file_atomically(const std::string& path, std::string_view bytes) {
  struct stat st {};
  if (::stat(path.c_str(), &st) == 0 && !S_ISREG(st.st_mode)) {
    if (S_ISDIR(st.st_mode)) throw IoError(path + ": cannot write, it is a directory");
    // A device or FIFO named on purpose (/dev/null, /dev/stdout): no rename possible, but every
    // write is still checked, so /dev/full fails with ENOSPC. O_NONBLOCK: a FIFO without a reader
    // fails (ENXIO) instead of waiting.
    Descriptor fd(::open(path.c_str(), O_WRONLY | O_NONBLOCK | O_CLOEXEC | O_NOCTTY));
    if (fd.get() < 0) throw IoError(path + ": cannot open for writing (" + reason() + ")");
    const int flags = ::fcntl(fd.get(), F_GETFL);
    if (flags >= 0) ::fcntl(fd.get(), F_SETFL, flags & ~O_NONBLOCK);
    write_all(fd.get(), bytes, path);
    if (fd.close() != 0) throw IoError(path + ": cannot write (" + reason() + ")");
    return;
  }
  // Replace the file a symbolic link names, not the link.
  std::string target = path;
  const bool exists = ::stat(path.c_str(), &st) == 0;
  if (exists) {
    char resolved[PATH_MAX];
    if (::realpath(path.c_str(), resolved) != nullptr) target = resolved;
  } else if (errno != ENOENT) {
    throw IoError(path + ": cannot write (" + reason() + ")");
  }
  const std::string directory = directory_of(target);
  std::string name =
      target.substr(target.find_last_of('/') == std::string::npos ? 0 : target.find_last_of('/') + 1);
  std::string temporary = (directory == "." && target.find('/') == std::string::npos ? "" : directory + "/") +
                          "." + name + ".tmp.XXXXXX";
  Descriptor fd(::mkstemp(temporary.data()));
  if (fd.get() < 0)
    throw IoError(path + ": cannot write, no file can be created in '" + directory + "' (" + reason() + ")");
  try {
    write_all(fd.get(), bytes, path);
    // mkstemp creates 0600; give the file the mode a new file gets, or the old file's mode.
    mode_t mode = 0;
    if (exists) {
      mode = st.st_mode & 07777;
    } else {
      const mode_t mask = ::umask(0);
      ::umask(mask);
      mode = 0666 & ~mask;
    }
    if (::fchmod(fd.get(), mode) != 0) throw IoError(path + ": cannot set the file mode (" + reason() + ")");
    if (::fdatasync(fd.get()) != 0) throw IoError(path + ": cannot write (" + reason() + ")");
    if (fd.close() != 0) throw IoError(path + ": cannot write (" + reason() + ")");
    if (::rename(temporary.c_str(), target.c_str()) != 0)
      throw IoError(path + ": cannot replace the file (" + reason() + ")");
  } catch (...) {
    ::unlink(temporary.c_str());
    throw;
  }
}

}  // namespace morph

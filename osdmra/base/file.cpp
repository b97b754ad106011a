#include "osdmra/base/file.h"

#include <fcntl.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <streambuf>
#include <string_view>

#include "osdmra/base/error.h"

namespace osdmra {
namespace {

std::string errnoText(int err) {
  return err ? std::strerror(err) : "unknown error";
}

// A stream buffer over a POSIX file descriptor, so that the file can be synced
// before it is renamed (std::ofstream cannot fsync). Records the first error.
class FdBuffer : public std::streambuf {
 public:
  explicit FdBuffer(int fd) : fd_(fd) { setp(buf_, buf_ + sizeof buf_); }
  int error() const { return error_; }

 protected:
  int overflow(int c) override {
    if (!drain()) return traits_type::eof();
    if (c != traits_type::eof()) {
      *pptr() = static_cast<char>(c);
      pbump(1);
    }
    return traits_type::not_eof(c);
  }
  int sync() override { return drain() ? 0 : -1; }

 private:
  bool drain() {
    const char* p = pbase();
    while (p < pptr()) {
      const ssize_t n = ::write(fd_, p, static_cast<std::size_t>(pptr() - p));
      if (n < 0 && errno == EINTR) continue;
      if (n <= 0) {
        if (!error_) error_ = n < 0 ? errno : EIO;
        return false;
      }
      p += n;
    }
    setp(buf_, buf_ + sizeof buf_);
    return true;
  }
  int fd_;
  int error_ = 0;
  char buf_[1 << 16];
};

// The temporary file: a fresh, exclusively created name next to the target.
struct TempFile {
  std::string name;
  int fd = -1;
  bool committed = false;
  explicit TempFile(const std::string& path) {
    static std::atomic<unsigned> counter{0};
    int err = 0;
    for (int attempt = 0; attempt < 100 && fd < 0; ++attempt) {
      name = path + ".tmp-" + std::to_string(::getpid()) + "-" + std::to_string(counter++);
      fd = ::open(name.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
      err = errno;
      if (fd < 0 && err != EEXIST) break;
    }
    if (fd < 0)
      throw Error(path + ": cannot create temporary file " + name + ": " + errnoText(err));
  }
  ~TempFile() {
    if (fd >= 0) ::close(fd);
    if (!committed) std::remove(name.c_str());
  }
};

}  // namespace

void writeFileAtomically(const std::string& path, const std::function<void(std::ostream&)>& write) {
  TempFile tmp(path);
  const auto fail = [&](const std::string& what, int err) {
    throw Error(path + ": " + what + " (temporary file " + tmp.name + "): " + errnoText(err));
  };
  {
    FdBuffer buffer(tmp.fd);
    std::ostream out(&buffer);
    try {
      write(out);
    } catch (const Error& e) {
      if (std::string_view(e.what()).rfind(path, 0) == 0) throw;
      throw Error(path + ": " + e.what());
    }
    out.flush();
    if (!out || buffer.error()) fail("write failed (disk full?)", buffer.error());
  }
  // fsync before rename, or a crash could leave the new name on empty data.
  if (::fsync(tmp.fd) != 0) fail("write failed", errno);
  const int closed = ::close(tmp.fd);
  tmp.fd = -1;
  if (closed != 0) fail("write failed", errno);
  if (std::rename(tmp.name.c_str(), path.c_str()) != 0) fail("cannot replace the file", errno);
  tmp.committed = true;
}

void writeTextFile(const std::string& path, const std::string& text) {
  writeFileAtomically(path, [&](std::ostream& out) {
    out.write(text.data(), static_cast<std::streamsize>(text.size()));
  });
}

}  // namespace osdmra

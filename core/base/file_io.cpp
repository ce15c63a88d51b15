// core/base/file_io.cpp: POSIX open/fstat/read and write/fsync/rename with every result checked.
#include "core/base/file_io.h"

#include <fcntl.h>
#include <signal.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cctype>
#include <cerrno>
#include <chrono>
#include <cstring>
#include <filesystem>

#include "core/base/error.h"

namespace pv {
namespace {

namespace fs = std::filesystem;

std::string errno_text(int e) { return std::strerror(e); }

std::string folder_of(const std::string& path) {
    const fs::path dir = fs::path(path).parent_path();
    return dir.empty() ? std::string(".") : dir.string();
}

// Opens `path` for reading without blocking (a FIFO with no writer would block open() itself) and checks that it
// is a regular file. Returns the descriptor and its size.
int open_regular(const std::string& path, const char* what, uint64_t& size) {
    const int fd = ::open(path.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC | O_NOCTTY);
    if (fd < 0) {
        const int e = errno;
        if (e == ENOENT || e == ENOTDIR) throw Error(path + ": no such file; expected " + what);
        throw Error(path + ": cannot open for reading: " + errno_text(e) + "; expected " + what);
    }
    struct stat st {};
    if (::fstat(fd, &st) != 0) {
        const int e = errno;
        ::close(fd);
        throw Error(path + ": cannot read: " + errno_text(e));
    }
    if (!S_ISREG(st.st_mode)) {
        ::close(fd);
        const char* kind = S_ISDIR(st.st_mode)                          ? "is a folder"
                           : S_ISFIFO(st.st_mode)                       ? "is a FIFO"
                           : S_ISCHR(st.st_mode) || S_ISBLK(st.st_mode) ? "is a device"
                                                                        : "is not a regular file";
        throw Error(path + ": " + kind + "; expected " + what + " (only regular files are read)");
    }
    size = uint64_t(st.st_size);
    return fd;
}

// ".pv-<pid>-<serial>.tmp": the pid of a writer, so that a later run can tell whether the writer still lives.
bool parse_temp_name(const std::string& name, long& pid) {
    const std::string prefix = ".pv-", suffix = ".tmp";
    if (name.size() <= prefix.size() + suffix.size() || name.compare(0, prefix.size(), prefix) != 0 ||
        name.compare(name.size() - suffix.size(), suffix.size(), suffix) != 0)
        return false;
    const std::string mid = name.substr(prefix.size(), name.size() - prefix.size() - suffix.size());
    const size_t dash = mid.find('-');
    if (dash == 0 || dash == std::string::npos || dash + 1 == mid.size() || dash > 10) return false;
    for (size_t i = 0; i < mid.size(); ++i)
        if (i != dash && !std::isdigit(static_cast<unsigned char>(mid[i]))) return false;
    pid = std::stol(mid.substr(0, dash));
    return pid > 0;
}

// Removes temporary files of writers that no longer exist. The age test (a minute without a write) keeps the
// files of a live writer in another pid namespace sharing the folder, whose pid kill() cannot see.
void remove_stale_temps(const std::string& dir) {
    std::error_code ec;
    const auto now = fs::file_time_type::clock::now();
    for (fs::directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec)) {
        long pid = 0;
        if (!parse_temp_name(it->path().filename().string(), pid) || pid == long(::getpid())) continue;
        if (::kill(pid_t(pid), 0) == 0 || errno != ESRCH) continue;
        std::error_code ec2;
        const auto mtime = fs::last_write_time(it->path(), ec2);
        if (ec2 || now - mtime < std::chrono::minutes(1)) continue;
        fs::remove(it->path(), ec2);
    }
}

std::atomic<unsigned> g_serial{0};

// Creates a fresh temporary file in `dir`; returns its descriptor and sets `tmp`. Throws naming `path`.
int create_temp(const std::string& path, const std::string& dir, std::string& tmp) {
    for (int attempt = 0; attempt < 100; ++attempt) {
        tmp = (fs::path(dir) / atomic_temp_name(long(::getpid()), g_serial++)).string();
        const int fd = ::open(tmp.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
        if (fd >= 0) return fd;
        const int e = errno;
        if (e == EEXIST) continue;
        std::error_code ec;
        if (e == ENOENT || !fs::is_directory(dir, ec))
            throw Error(path + ": cannot write: folder '" + dir + "' does not exist");
        throw Error(path + ": cannot write: " + errno_text(e));
    }
    throw Error(path + ": cannot write: no free temporary name in '" + dir + "'");
}

}  // namespace

std::string atomic_temp_name(long pid, unsigned serial) {
    return ".pv-" + std::to_string(pid) + "-" + std::to_string(serial) + ".tmp";
}

uint64_t regular_file_size(const std::string& path, const char* what) {
    uint64_t size = 0;
    ::close(open_regular(path, what, size));
    return size;
}

namespace {
// Reads `n` bytes from `fd` (fewer if the file shrank meanwhile) and closes it.
template <class Bytes>
Bytes read_from(int fd, const std::string& path, size_t n) {
    Bytes bytes(n, 0);
    size_t done = 0;
    while (done < bytes.size()) {
        const ssize_t r = ::read(fd, bytes.data() + done, bytes.size() - done);
        if (r < 0 && errno == EINTR) continue;
        if (r < 0) {
            const int e = errno;
            ::close(fd);
            throw Error(path + ": read error: " + errno_text(e));
        }
        if (r == 0) break;
        done += size_t(r);
    }
    ::close(fd);
    bytes.resize(done);
    return bytes;
}
}  // namespace

std::string read_regular_file_prefix(const std::string& path, size_t n, const char* what) {
    uint64_t size = 0;
    const int fd = open_regular(path, what, size);
    return read_from<std::string>(fd, path, size_t(std::min<uint64_t>(size, n)));
}

std::string read_regular_file(const std::string& path, uint64_t max_bytes, const char* what) {
    uint64_t size = 0;
    const int fd = open_regular(path, what, size);
    if (size > max_bytes) {
        ::close(fd);
        throw Error(path + ": the file is " + std::to_string(size) + " bytes; the limit for " + what + " is " +
                    std::to_string(max_bytes));
    }
    return read_from<std::string>(fd, path, size_t(size));
}

std::vector<unsigned char> read_regular_file_bytes(const std::string& path, uint64_t max_bytes, const char* what) {
    uint64_t size = 0;
    const int fd = open_regular(path, what, size);
    if (size > max_bytes) {
        ::close(fd);
        throw Error(path + ": the file is " + std::to_string(size) + " bytes; the limit for " + what + " is " +
                    std::to_string(max_bytes));
    }
    return read_from<std::vector<unsigned char>>(fd, path, size_t(size));
}

void write_all(int fd, const void* data, size_t size, const std::string& path) {
    const char* p = static_cast<const char*>(data);
    while (size > 0) {
        const ssize_t n = ::write(fd, p, size);
        if (n < 0 && errno == EINTR) continue;
        if (n <= 0) throw Error(path + ": cannot write: " + errno_text(n < 0 ? errno : ENOSPC));
        p += n;
        size -= size_t(n);
    }
}

void write_file_atomically(const std::string& path, const std::function<void(int fd)>& write) {
    const std::string dir = folder_of(path);
    remove_stale_temps(dir);
    std::string tmp;
    int fd = create_temp(path, dir, tmp);
    auto fail = [&](int e) {
        if (fd >= 0) ::close(fd);
        ::unlink(tmp.c_str());
        std::error_code ec;
        if (e == EISDIR || fs::is_directory(path, ec)) throw Error(path + ": cannot write: it is a folder");
        throw Error(path + ": cannot write: " + errno_text(e));
    };
    try {
        write(fd);
    } catch (...) {
        ::close(fd);
        ::unlink(tmp.c_str());
        throw;
    }
    if (::fsync(fd) != 0) fail(errno);
    const int closed = ::close(fd);
    fd = -1;
    if (closed != 0) fail(errno);
    if (::rename(tmp.c_str(), path.c_str()) != 0) fail(errno);
    // Make the rename itself durable; a failure here leaves a whole file either way.
    if (const int dfd = ::open(dir.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC); dfd >= 0) {
        ::fsync(dfd);
        ::close(dfd);
    }
}

void check_writable(const std::string& path) {
    std::error_code ec;
    if (fs::is_directory(path, ec)) throw Error(path + ": cannot write: it is a folder");
    const std::string dir = folder_of(path);
    std::string tmp;
    const int fd = create_temp(path, dir, tmp);
    ::close(fd);
    ::unlink(tmp.c_str());
}

}  // namespace pv

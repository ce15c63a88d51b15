// core/base/file_io.h: reading untrusted files and writing outputs whole. Reads accept regular files only (a FIFO,
// a device such as /dev/zero or a directory is refused before a byte is read) up to a size limit. Writes go to a
// short temporary name in the destination's folder, every write checked, fsync and close checked, then rename():
// a crash or a full disk never leaves half a file at the final name. Failures throw pv::Error naming the file.
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

namespace pv {

// The bytes of the regular file `path`, at most `max_bytes` of them. `what` completes "expected ..." in messages
// ("a scene file", "an image"). Throws pv::Error: missing, not a regular file, larger than max_bytes, read error.
std::string read_regular_file(const std::string& path, uint64_t max_bytes, const char* what);

// The same into a byte vector (what tinygltf takes, without a second copy of the file).
std::vector<unsigned char> read_regular_file_bytes(const std::string& path, uint64_t max_bytes, const char* what);

// The first `n` bytes (fewer if the file is shorter) of the regular file `path`, same checks.
std::string read_regular_file_prefix(const std::string& path, size_t n, const char* what);

// Size of the regular file `path` after the same checks as read_regular_file, without reading it.
uint64_t regular_file_size(const std::string& path, const char* what);

// Writes `size` bytes to `fd`, retrying short writes and EINTR. Throws pv::Error "<path>: cannot write: <errno>".
void write_all(int fd, const void* data, size_t size, const std::string& path);

// Creates `path` atomically: `write` gets a file descriptor open for writing on a temporary file in the same
// folder and writes the whole content (with write_all, pwrite, or anything that throws on failure). Then fsync,
// close and rename, each checked; on any failure the temporary file is removed and pv::Error names `path` with
// the reason (errno captured before the clean-up). Temporary names are ".pv-<pid>-<n>.tmp" whatever the length
// of the final name; ones left by a process that no longer exists (SIGKILL, power loss) and older than a minute
// are removed by the next write into that folder.
void write_file_atomically(const std::string& path, const std::function<void(int fd)>& write);

// Checks before a long computation that `path` can be created: its folder exists and accepts a new file (one is
// created and removed), and `path` is not a folder. Throws pv::Error naming `path` and the reason.
void check_writable(const std::string& path);

// The temporary-file name pattern of write_file_atomically for process `pid` (tests use it).
std::string atomic_temp_name(long pid, unsigned serial);

}  // namespace pv

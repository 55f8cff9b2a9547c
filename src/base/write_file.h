// Writing files so that a reader sees the old file or the new one, never part of one, and a
// failure leaves the old one: a temporary file beside it (fsync'ed), then rename(). Several files
// are written together: every temporary first, then the renames. Used for images, crop pieces and
// the OBJ files and scenes the tools write.
#pragma once

#include <cstdint>
#include <functional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace raycast {

/// The file that writing `path` replaces: `path` itself, or where the symbolic link it names
/// leads (followed link by link, a relative target read from the link's folder), so that a
/// written link keeps pointing at the new file, as a shell's `>` leaves it. `error` is 0, or the
/// errno that stopped it (ELOOP for a loop of links); the path is then `path`.
std::string replaced_path(const std::string& path, int& error);

/// Writes each (path, bytes) atomically, all of them together: a failure before the renames (a
/// full disk, a quota) replaces none. Throws InputError(path, "cannot write <what>: <reason>"),
/// naming the file that failed; `what` is "image", "OBJ file", ...
void write_files_atomically(const std::vector<std::pair<std::string, std::vector<uint8_t>>>& files,
                            const char* what);

/// One file, as above.
void write_file_atomically(const std::string& path, const std::vector<uint8_t>& bytes, const char* what);
void write_file_atomically(const std::string& path, std::string_view text, const char* what);

/// One file whose bytes are made as they are written (a mesh too big to hold as text): `fill`
/// writes them to the file descriptor it is given and returns 0, or the errno of a failed write.
void write_file_atomically(const std::string& path, const std::function<int(int fd)>& fill, const char* what);

}  // namespace raycast

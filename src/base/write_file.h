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

/// The folder a path names its last component in: "." for a bare name, "/" at the root.
std::string folder_of(const std::string& path);

/// Where writing a path goes, found by one walk along its links.
struct WriteTarget {
    /// The file a rename replaces: the path itself, or where the symbolic link it names leads
    /// (followed link by link, a relative target read from the link's folder), so that a written
    /// link keeps pointing at the new file, as a shell's `>` leaves it. The path itself when
    /// in_place or on an error.
    std::string file;
    /// Written into as it is, with no temporary and no rename: a pipe, a terminal or a device
    /// (/dev/null), or a file named through /proc's links to open files (/dev/stdout, /dev/fd/3),
    /// which only the kernel can follow. A rename would put a plain file in their place.
    bool in_place = false;
    /// 0, or the errno that stopped the walk: ELOOP for a loop of links, EACCES for another
    /// user's link in a sticky folder anyone may write to (/tmp), which is not followed, as the
    /// kernel's fs.protected_symlinks follows none.
    int error = 0;
};
WriteTarget write_target(const std::string& path);

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

#include "base/write_file.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>
#ifdef __linux__
#include <linux/magic.h>
#include <sys/vfs.h>
#endif

#include <atomic>
#include <cerrno>
#include <cstring>
#include <functional>

#include "base/error.h"

namespace raycast {
namespace {

// A file to write: where, and what writes its bytes to an open file descriptor (returning 0, or
// the errno of a failed write).
struct Pending {
    const std::string& path;
    std::function<int(int fd)> fill;
};

InputError cannot_write(const std::string& path, const char* what, int error) {
    return InputError(path, std::string("cannot write ") + what + ": " + std::strerror(error));
}

// Writes all the bytes (again where a write stops short or is interrupted); returns 0, or the
// errno of the failed write.
int write_all(int fd, std::string_view bytes) {
    size_t done = 0;
    while (done < bytes.size()) {
        const ssize_t written = ::write(fd, bytes.data() + done, bytes.size() - done);
        if (written < 0) {
            if (errno == EINTR) continue;
            return errno;
        }
        done += static_cast<size_t>(written);
    }
    return 0;
}

// Writes the bytes to a fresh temporary file beside `target` (the file's WriteTarget; fsync'ed)
// and returns its name; on any failure removes it and throws, naming the file as it was given.
std::string write_temporary(const Pending& file, const std::string& target, const char* what) {
    const size_t slash = target.rfind('/');
    const std::string directory = slash == std::string::npos ? "" : target.substr(0, slash + 1);
    // Keep the temporary's name within NAME_MAX whatever the file name's length.
    const std::string base = (slash == std::string::npos ? target : target.substr(slash + 1)).substr(0, 100);
    static std::atomic<unsigned> counter{0};
    std::string temporary;
    int fd = -1;
    // O_EXCL with a fresh name, rather than mkstemp, so the file gets the usual umask-based permissions.
    for (int attempt = 0; attempt < 100 && fd < 0; ++attempt) {
        temporary =
            directory + "." + base + string_printf(".%ld.%u.tmp", static_cast<long>(::getpid()), counter.fetch_add(1));
        fd = ::open(temporary.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
        if (fd < 0 && errno != EEXIST) break;
    }
    if (fd < 0) throw cannot_write(file.path, what, errno);
    int error = 0;
    try {
        error = file.fill(fd);
    } catch (...) {  // out of memory while making the bytes, say: no temporary is left behind
        ::close(fd);
        ::unlink(temporary.c_str());
        throw;
    }
    // Without fsync a crash soon after rename() could leave an empty file in place of both versions.
    if (error == 0 && ::fsync(fd) != 0) error = errno;
    if (::close(fd) != 0 && error == 0) error = errno;
    if (error != 0) {
        ::unlink(temporary.c_str());
        throw cannot_write(file.path, what, error);
    }
    return temporary;
}

// How many links write_target follows: Linux's own limit for a path (MAXSYMLINKS).
constexpr int kMaxLinksFollowed = 40;

// Whether the folder of `path` is in /proc (however reached: /dev/fd is a link to /proc/self/fd).
bool in_proc(const std::string& path) {
#ifdef __linux__
    struct statfs fs;
    return ::statfs(folder_of(path).c_str(), &fs) == 0 && fs.f_type == PROC_SUPER_MAGIC;
#else
    return path.compare(0, 6, "/proc/") == 0;
#endif
}

// write_target's walk along the links. It stops at a link in /proc, where links to open files
// (/proc/self/fd/1, what /dev/stdout leads to) read as text that is no path ("pipe:[7]",
// "/tmp/x (deleted)"): only the kernel can follow those, and the file is written in place.
WriteTarget follow_links(const std::string& path) {
    std::string current = path;
    for (int followed = 0;; ++followed) {
        struct stat entry;
        if (::lstat(current.c_str(), &entry) != 0 || !S_ISLNK(entry.st_mode)) return {current, false, 0};
        if (in_proc(current)) return {path, true, 0};
        if (followed == kMaxLinksFollowed) return {path, false, ELOOP};
        // As the kernel's fs.protected_symlinks (on by default in most distributions): a link in a
        // sticky folder anyone may write to (/tmp) is followed only by its owner or the folder's,
        // so that no one can point another user's output at that user's files.
        struct stat folder;
        if (::stat(folder_of(current).c_str(), &folder) == 0 && (folder.st_mode & S_ISVTX) &&
            (folder.st_mode & S_IWOTH) && entry.st_uid != ::geteuid() && entry.st_uid != folder.st_uid)
            return {path, false, EACCES};
        std::string target(static_cast<size_t>(entry.st_size > 0 ? entry.st_size : 256) + 1, '\0');
        const ssize_t length = ::readlink(current.c_str(), target.data(), target.size());
        if (length <= 0) return {path, false, length < 0 ? errno : ENOENT};  // Linux has no empty links
        if (static_cast<size_t>(length) >= target.size()) continue;  // changed meanwhile: read it again
        target.resize(static_cast<size_t>(length));
        const size_t slash = current.rfind('/');
        current = target.front() == '/' || slash == std::string::npos ? target : current.substr(0, slash + 1) + target;
    }
}

void write_in_place(const Pending& file, const char* what) {
    const int fd = ::open(file.path.c_str(), O_WRONLY | O_TRUNC | O_CLOEXEC);
    if (fd < 0) throw cannot_write(file.path, what, errno);
    int error = 0;
    try {
        error = file.fill(fd);
    } catch (...) {
        ::close(fd);
        throw;
    }
    if (::close(fd) != 0 && error == 0) error = errno;
    if (error != 0) throw cannot_write(file.path, what, error);
}

// Every file's temporary first, then the renames: a full disk or a quota fails before any file
// is replaced, so a run that reports failure leaves every output as it was (a rename, the last
// step, rarely fails; then the temporaries left are removed). Special files are written last.
void write_together(const std::vector<Pending>& files, const char* what) {
    // A link is written through: its target is replaced, and the link left as it is.
    std::vector<WriteTarget> targets;
    for (const Pending& file : files) {
        targets.push_back(write_target(file.path));
        if (targets.back().error != 0) throw cannot_write(file.path, what, targets.back().error);
    }
    std::vector<std::string> temporaries(files.size());
    try {
        for (size_t i = 0; i < files.size(); ++i)
            if (!targets[i].in_place) temporaries[i] = write_temporary(files[i], targets[i].file, what);
    } catch (...) {
        for (const std::string& temporary : temporaries)
            if (!temporary.empty()) ::unlink(temporary.c_str());
        throw;
    }
    for (size_t i = 0; i < files.size(); ++i) {
        if (targets[i].in_place || ::rename(temporaries[i].c_str(), targets[i].file.c_str()) == 0) continue;
        const int error = errno;
        for (size_t j = i; j < files.size(); ++j)
            if (!temporaries[j].empty()) ::unlink(temporaries[j].c_str());
        throw cannot_write(files[i].path, what, error);
    }
    for (size_t i = 0; i < files.size(); ++i)
        if (targets[i].in_place) write_in_place(files[i], what);
}

// Writes the bytes whole.
std::function<int(int)> fill_with(std::string_view bytes) {
    return [bytes](int fd) { return write_all(fd, bytes); };
}

std::string_view view_of(const std::vector<uint8_t>& bytes) {
    return {reinterpret_cast<const char*>(bytes.data()), bytes.size()};
}

}  // namespace

std::string folder_of(const std::string& path) {
    const size_t slash = path.rfind('/');
    return slash == std::string::npos ? std::string(".") : (slash == 0 ? std::string("/") : path.substr(0, slash));
}

WriteTarget write_target(const std::string& path) {
    struct stat info;
    if (::stat(path.c_str(), &info) == 0 && !S_ISREG(info.st_mode) && !S_ISDIR(info.st_mode)) return {path, true, 0};
    return follow_links(path);
}

void write_files_atomically(const std::vector<std::pair<std::string, std::vector<uint8_t>>>& files,
                            const char* what) {
    std::vector<Pending> pending;
    for (const auto& [path, bytes] : files) pending.push_back({path, fill_with(view_of(bytes))});
    write_together(pending, what);
}

void write_file_atomically(const std::string& path, const std::vector<uint8_t>& bytes, const char* what) {
    write_together({{path, fill_with(view_of(bytes))}}, what);
}

void write_file_atomically(const std::string& path, std::string_view text, const char* what) {
    write_together({{path, fill_with(text)}}, what);
}

void write_file_atomically(const std::string& path, const std::function<int(int fd)>& fill, const char* what) {
    write_together({{path, fill}}, what);
}

}  // namespace raycast

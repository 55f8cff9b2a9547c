#include "base/write_file.h"

#include <gtest/gtest.h>
#include <sys/stat.h>
#include <fcntl.h>
#include <unistd.h>

#include <cerrno>

#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <functional>
#include <iterator>
#include <new>
#include <string>
#include <thread>

#include "base/error.h"

namespace raycast {
namespace {

std::string fresh_dir() {
    std::string pattern = ::testing::TempDir() + "raycast_write_file_XXXXXX";
    EXPECT_NE(::mkdtemp(pattern.data()), nullptr);
    return pattern;
}

std::string contents(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

// A plain file is replaced whole; a pipe (or a device, /dev/null) is written into: a rename would
// have put a plain file in its place, and the reader at the pipe got nothing.
TEST(WriteFileTest, PlainFilesAreReplacedAndPipesWrittenInto) {
    const std::string dir = fresh_dir();
    const std::string plain = dir + "/plain.txt", pipe = dir + "/pipe";
    write_file_atomically(plain, std::string_view("old"), "file");
    write_file_atomically(plain, std::string_view("new text"), "file");
    EXPECT_EQ(contents(plain), "new text");
    ASSERT_EQ(::mkfifo(pipe.c_str(), 0600), 0);
    std::string received;
    std::thread reader([&] { received = contents(pipe); });
    write_file_atomically(pipe, std::string_view("through the pipe"), "file");
    reader.join();
    EXPECT_EQ(received, "through the pipe");
    struct stat info;
    ASSERT_EQ(::stat(pipe.c_str(), &info), 0);
    EXPECT_TRUE(S_ISFIFO(info.st_mode));
    std::remove(plain.c_str());
    std::remove(pipe.c_str());
    std::remove(dir.c_str());
}

bool is_link(const std::string& path) {
    struct stat info;
    return ::lstat(path.c_str(), &info) == 0 && S_ISLNK(info.st_mode);
}

// A symbolic link is written through, as a shell's `>` writes: the file it leads to is replaced
// and the link stays a link (a rename onto the link had put a plain file in its place and left
// the file it pointed at as it was). Relative targets are read from the link's own folder, links
// to links are followed, and a link to a file not yet there creates that file.
TEST(WriteFileTest, LinksAreWrittenThrough) {
    const std::string dir = fresh_dir();
    ASSERT_EQ(::mkdir((dir + "/images").c_str(), 0700), 0);
    const std::string target = dir + "/images/latest.ppm";
    write_file_atomically(target, std::string_view("old"), "image");
    const std::string relative = dir + "/relative.ppm", absolute = dir + "/absolute.ppm", chain = dir + "/chain.ppm";
    ASSERT_EQ(::symlink("images/latest.ppm", relative.c_str()), 0);
    ASSERT_EQ(::symlink(target.c_str(), absolute.c_str()), 0);
    ASSERT_EQ(::symlink("relative.ppm", chain.c_str()), 0);
    EXPECT_EQ(write_target(chain).file, dir + "/images/latest.ppm");
    EXPECT_EQ(write_target(chain).error, 0);
    EXPECT_EQ(write_target(target).file, target);
    EXPECT_EQ(write_target(target).error, 0);

    write_file_atomically(relative, std::string_view("through a relative link"), "image");
    EXPECT_EQ(contents(target), "through a relative link");
    write_files_atomically({{absolute, {'a', 'b', 's'}}, {chain, {'c', 'h', 'a', 'i', 'n'}}}, "image");
    EXPECT_EQ(contents(target), "chain");  // both lead there; the last rename wins
    for (const std::string& link : {relative, absolute, chain}) EXPECT_TRUE(is_link(link)) << link;

    const std::string dangling = dir + "/dangling.ppm", created = dir + "/images/new.ppm";
    ASSERT_EQ(::symlink("images/new.ppm", dangling.c_str()), 0);
    write_file_atomically(dangling, std::string_view("created"), "image");
    EXPECT_TRUE(is_link(dangling));
    EXPECT_EQ(contents(created), "created");
    for (const std::string& path : {relative, absolute, chain, dangling, target, created}) std::remove(path.c_str());
    std::remove((dir + "/images").c_str());
    std::remove(dir.c_str());
}

// A loop of links is an error that names the file as it was given, and nothing is written.
TEST(WriteFileTest, ALoopOfLinksIsRefused) {
    const std::string dir = fresh_dir();
    const std::string a = dir + "/a.ppm", b = dir + "/b.ppm";
    ASSERT_EQ(::symlink("b.ppm", a.c_str()), 0);
    ASSERT_EQ(::symlink("a.ppm", b.c_str()), 0);
    EXPECT_EQ(write_target(a).file, a);
    EXPECT_EQ(write_target(a).error, ELOOP);
    try {
        write_file_atomically(a, std::string_view("x"), "image");
        ADD_FAILURE() << "a loop of links was written";
    } catch (const InputError& e) {
        EXPECT_EQ(std::string(e.what()), a + ": error: cannot write image: Too many levels of symbolic links\n");
    }
    std::remove(a.c_str());
    std::remove(b.c_str());
    EXPECT_EQ(::rmdir(dir.c_str()), 0) << "a temporary was left behind";
}

// Another user's link in a sticky folder anyone may write to (/tmp) is not followed, as the
// kernel's fs.protected_symlinks follows none: such a link had let anyone point another user's
// image at that user's files. Root's test makes the link nobody's with lchown.
TEST(WriteFileTest, AnotherUsersLinkInAStickyFolderIsNotFollowed) {
    if (::geteuid() != 0) GTEST_SKIP() << "needs root to give a link to another user";
    const std::string dir = fresh_dir();
    ASSERT_EQ(::chmod(dir.c_str(), 01777), 0);
    const std::string victim = dir + "/notes.txt", link = dir + "/out.ppm";
    write_file_atomically(victim, std::string_view("precious"), "file");
    ASSERT_EQ(::symlink("notes.txt", link.c_str()), 0);
    ASSERT_EQ(::lchown(link.c_str(), 65534, 65534), 0);
    EXPECT_EQ(write_target(link).file, link);
    EXPECT_EQ(write_target(link).error, EACCES);
    EXPECT_THROW(write_file_atomically(link, std::string_view("image"), "image"), InputError);
    EXPECT_EQ(contents(victim), "precious");
    // Its owner's own link, or one in a folder that is not sticky, is followed.
    ASSERT_EQ(::lchown(link.c_str(), 0, 0), 0);
    EXPECT_EQ(write_target(link).file, victim);
    EXPECT_EQ(write_target(link).error, 0);
    std::remove(link.c_str());
    std::remove(victim.c_str());
    std::remove(dir.c_str());
}

// A fill function that throws (out of memory while it makes the bytes) leaves no temporary.
TEST(WriteFileTest, AFillThatThrowsLeavesNothingBehind) {
    const std::string dir = fresh_dir();
    const std::function<int(int)> failing = [](int fd) -> int {
        if (::write(fd, "partial", 7) != 7) return EIO;
        throw std::bad_alloc();
    };
    EXPECT_THROW(write_file_atomically(dir + "/mesh.obj", failing, "OBJ file"), std::bad_alloc);
    EXPECT_EQ(::rmdir(dir.c_str()), 0) << "a temporary was left behind";
}

// /dev/stdout and /dev/fd/N lead through /proc's links to open files, whose text is no path
// ("pipe:[7]", "/tmp/x (deleted)"): such outputs are written into, as the shell's > writes them,
// never renamed onto (a stray file named "x (deleted)" had been made).
TEST(WriteFileTest, OpenFilesNamedThroughProcAreWrittenInto) {
    EXPECT_TRUE(write_target("/dev/stdout").in_place);
    EXPECT_TRUE(write_target("/dev/null").in_place);
    const std::string dir = fresh_dir();
    const std::string gone = dir + "/gone.obj";
    const int fd = ::open(gone.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0600);
    ASSERT_GE(fd, 0);
    ASSERT_EQ(::unlink(gone.c_str()), 0);
    const std::string through = "/dev/fd/" + std::to_string(fd);
    EXPECT_FALSE(write_target(dir + "/plain.obj").in_place);
    EXPECT_TRUE(write_target(through).in_place);
    write_file_atomically(through, std::string_view("v 0 0 0\n"), "OBJ file");
    struct stat info;
    ASSERT_EQ(::fstat(fd, &info), 0);
    EXPECT_EQ(info.st_size, 8);
    ::close(fd);
    EXPECT_EQ(::rmdir(dir.c_str()), 0) << "a stray file was made";
}

}  // namespace
}  // namespace raycast

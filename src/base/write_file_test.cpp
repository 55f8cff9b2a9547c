#include "base/write_file.h"

#include <gtest/gtest.h>
#include <sys/stat.h>

#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <iterator>
#include <string>
#include <thread>

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

}  // namespace
}  // namespace raycast

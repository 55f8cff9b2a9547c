// The viewer's file watcher: a save that begins after wait() returned is counted before its writer
// closes the file, wait() then lasts until the writer is done, other files in the folder do not
// count, and a writer that keeps changing the file is not waited for forever. Most tests read no
// clock: they check what changed_since_wait() says, which depends on how the last wait ended.
#include "view/file_watcher.h"

#include <gtest/gtest.h>
#include <fcntl.h>
#include <stdlib.h>
#include <sys/stat.h>
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <fstream>
#include <iterator>
#include <memory>
#include <string>
#include <thread>

namespace raycast {
namespace {

class FileWatcherTest : public ::testing::Test {
protected:
    void SetUp() override {
        if (!files_.notified()) GTEST_SKIP() << "no inotify here: the watcher only looks every so often";
        std::string pattern = ::testing::TempDir() + "raycast_file_watcher_XXXXXX";
        ASSERT_NE(::mkdtemp(pattern.data()), nullptr);
        dir_ = pattern;
        write(scene(), "Group { numObjects 0 }\n");
        files_.watch({scene()});
        files_.wait(0);  // nothing has happened since watch(): returns at once, settled
    }
    std::string scene() const { return dir_ + "/s.txt"; }
    void write(const std::string& path, const std::string& text) { std::ofstream(path, std::ios::trunc) << text; }
    std::string contents(const std::string& path) {
        std::ifstream in(path, std::ios::binary);
        return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
    }

    FileWatcher files_;
    std::string dir_;
};

// The race the viewer had: its periodic look found the file changed, read it, and showed it,
// while the writer had only truncated it. The truncation is counted at once; wait() then returns
// only when the writer has closed the file, and the file is whole.
TEST_F(FileWatcherTest, ASaveBegunAfterTheWaitIsCountedAndWaitedFor) {
    EXPECT_FALSE(files_.changed_since_wait());
    const std::string saved = "Group { numObjects 1 Sphere { center 0 0 0 radius 1 } }\n";
    std::thread writer;
    {
        auto out = std::make_unique<std::ofstream>(scene(), std::ios::trunc);  // empty from here
        ASSERT_TRUE(*out);
        EXPECT_TRUE(files_.changed_since_wait()) << "a truncation was not counted";
        EXPECT_TRUE(files_.changed_since_wait()) << "counted once, then forgotten before the wait";
        writer = std::thread([out = std::move(out), &saved]() mutable {
            std::this_thread::sleep_for(std::chrono::milliseconds(100));
            *out << saved.substr(0, 10) << std::flush;
            std::this_thread::sleep_for(std::chrono::milliseconds(100));
            *out << saved.substr(10);
            out.reset();  // closes
        });
    }
    files_.wait(5000);
    EXPECT_EQ(contents(scene()), saved) << "wait() returned before the writer closed the file";
    writer.join();
    EXPECT_FALSE(files_.changed_since_wait());
}

// A save counted by changed_since_wait() (and so read from the queue already) is waited for at
// once: the next wait() does not first sit out its look's time for events that have been read.
TEST_F(FileWatcherTest, ASaveAlreadyCountedIsNotWaitedForAgain) {
    write(scene(), "Group { numObjects 0 }\n");  // truncated, written and closed
    EXPECT_TRUE(files_.changed_since_wait());
    const auto start = std::chrono::steady_clock::now();
    files_.wait(20000);
    // The margin is three orders of magnitude: settling takes kQuietMilliseconds.
    EXPECT_LT(std::chrono::steady_clock::now() - start, std::chrono::seconds(10)) << "waited for the look";
}

// Editors write swap and backup files beside the scene: they are no reason to drop a load.
TEST_F(FileWatcherTest, OtherFilesInTheFolderDoNotCount) {
    write(dir_ + "/s.txt.swp", "x");
    write(dir_ + "/s.txt~", "y");
    EXPECT_FALSE(files_.changed_since_wait());
    write(scene(), "Group { numObjects 0 }\n");
    EXPECT_TRUE(files_.changed_since_wait());
}

// A writer that keeps its file open and keeps writing: wait() gives up at its limit, and then no
// change counts until the next wait, so the viewer shows what was written so far.
TEST_F(FileWatcherTest, AWriterThatKeepsWritingIsNotWaitedForPastTheLimit) {
    std::ofstream out(scene(), std::ios::trunc);
    out << "Group {" << std::flush;
    files_.wait(5000);  // lasts kSettleLimitMilliseconds: the writer has not closed the file
    out << " numObjects 0" << std::flush;
    EXPECT_FALSE(files_.changed_since_wait()) << "a load after the limit would be dropped: nothing shown";
    out << " }\n";
    out.close();
    files_.wait(5000);  // the close: settled
    write(scene(), "Group { numObjects 0 }\n");
    EXPECT_TRUE(files_.changed_since_wait());
}

// A writer that saves again and again (truncates, writes, closes), faster than a load takes:
// every wait settles between two saves, and every load sees the next save begin. Its loads are
// dropped for two seconds at most, then one is shown. (Before, none ever was.)
TEST_F(FileWatcherTest, AWriterSavingAgainAndAgainStillGetsItsFileShown) {
    std::atomic<bool> stop{false};
    std::thread writer([&] {
        for (int i = 0; !stop.load() && i < 400; ++i) {  // 8 s at most
            write(scene(), "Group { numObjects 0 } # save " + std::to_string(i) + "\n");
            std::this_thread::sleep_for(std::chrono::milliseconds(20));
        }
    });
    int dropped = 0;
    bool shown = false;
    for (int look = 0; look < 60 && !shown; ++look) {  // 6 s at most
        files_.wait(200);
        std::this_thread::sleep_for(std::chrono::milliseconds(100));  // a load
        if (files_.changed_since_wait()) ++dropped;
        else shown = true;
    }
    stop = true;
    writer.join();
    EXPECT_GT(dropped, 0) << "no load saw a save begin: the writer did not keep up";
    EXPECT_TRUE(shown) << dropped << " loads dropped, none shown";
}

// A run of dropped loads ends when a look finds nothing to load (a file moved away and back
// keeps its time and size): a save two seconds later is a new run, and its load is dropped.
// (The run's start was kept, and that save's half-written file was shown.)
TEST_F(FileWatcherTest, ALookThatLoadsNothingEndsARunOfDroppedLoads) {
    ASSERT_EQ(::rename(scene().c_str(), (dir_ + "/moved.txt").c_str()), 0);
    ASSERT_EQ(::rename((dir_ + "/moved.txt").c_str(), scene().c_str()), 0);
    EXPECT_TRUE(files_.changed_since_wait());  // a load dropped
    files_.wait(0);  // the looks after it find the file as it was, load nothing and ask nothing
    files_.wait(0);
    std::this_thread::sleep_for(std::chrono::milliseconds(FileWatcher::kSettleLimitMilliseconds + 100));
    std::ofstream out(scene(), std::ios::trunc);  // a save begins while a load reads the file
    EXPECT_TRUE(files_.changed_since_wait()) << "the half-written file would be shown";
}

// A watched name made by a link has no writer and never closes: after one wait to the limit it
// is no longer waited for (it took every later wait to its limit, and no load was ever dropped).
TEST_F(FileWatcherTest, ANameWithNoWriterIsWaitedForOnce) {
    const std::string mesh = dir_ + "/mesh.obj";
    files_.watch({scene(), mesh});
    ASSERT_EQ(::symlink("s.txt", mesh.c_str()), 0);  // created, never closed
    files_.wait(5000);                                // to its limit
    write(scene(), "Group { numObjects 0 }\n");
    files_.wait(5000);  // settles: the save is closed, and the link is not waited for again
    write(scene(), "Group { numObjects 0 }\n");
    EXPECT_TRUE(files_.changed_since_wait()) << "the second wait went to its limit too";
}

// A file the scene no longer names is not waited for: its writer's close is never read, and
// every later wait would have lasted to its limit.
TEST_F(FileWatcherTest, AFileNoLongerWatchedIsNotWaitedFor) {
    const std::string mesh = dir_ + "/mesh.obj";
    write(mesh, "v 0 0 0\n");
    files_.watch({scene(), mesh});
    files_.wait(0);
    std::ofstream out(mesh, std::ios::trunc);  // the mesh's writer, still writing
    EXPECT_TRUE(files_.changed_since_wait());
    files_.watch({scene()});  // the scene stopped naming the mesh
    files_.wait(5000);        // settles: nothing watched is being written
    write(scene(), "Group { numObjects 0 }\n");
    EXPECT_TRUE(files_.changed_since_wait()) << "the wait lasted to its limit, waiting for the mesh";
}

// A save is heard of: the look after its wait loads it at once. A look after a wait that heard
// nothing does not: there the change may be a save whose writer has emptied the file and not yet
// queued the event (a double version in the browser test, 58 times in 250 saves under load).
TEST_F(FileWatcherTest, ASaveIsHeardOfAndALookWithNoEventIsNot) {
    write(scene(), "Group { numObjects 0 }\n");
    files_.wait(5000);
    EXPECT_TRUE(files_.heard_of_change());
    files_.wait(0);
    EXPECT_FALSE(files_.heard_of_change());
}

// A change that sends no event (here new access and modification times, whose IN_ATTRIB is not
// watched: a new modification time alone is an IN_MODIFY; a file system without inotify events)
// waits for one until kSettleLimitMilliseconds, then loads.
TEST_F(FileWatcherTest, AChangeWithNoEventIsLoadedAfterTheLimit) {
    const timespec times[2] = {{1000000, 0}, {1000000, 0}};
    ASSERT_EQ(::utimensat(AT_FDCWD, scene().c_str(), times, 0), 0);
    files_.wait(0);
    EXPECT_FALSE(files_.heard_of_change());
    files_.wait(0);
    EXPECT_FALSE(files_.heard_of_change()) << "waited for the event once only";
    std::this_thread::sleep_for(std::chrono::milliseconds(FileWatcher::kSettleLimitMilliseconds + 100));
    files_.wait(0);
    EXPECT_TRUE(files_.heard_of_change()) << "a change without events is never loaded";
    files_.wait(0);
    EXPECT_FALSE(files_.heard_of_change()) << "the next unheard change does not wait for its event";
}

// A load that found a file's time or size changed since before its read, with no event (a save
// whose truncation is not yet announced), is dropped like one during which an event came; the
// next wait() still looks first (no event is pending), and such drops stop after two seconds too.
TEST_F(FileWatcherTest, AFileFoundChangedByItsStampAloneDropsTheLoad) {
    EXPECT_TRUE(files_.changed_since_wait(true));
    EXPECT_FALSE(files_.changed_since_wait(false)) << "nothing changed: the load is shown";
    EXPECT_TRUE(files_.changed_since_wait(true));
    const auto start = std::chrono::steady_clock::now();
    files_.wait(100);
    EXPECT_GE(std::chrono::steady_clock::now() - start, std::chrono::milliseconds(100))
        << "no event is pending: the wait must look for the save's event, not return at once";
    EXPECT_FALSE(files_.heard_of_change());
    std::this_thread::sleep_for(std::chrono::milliseconds(FileWatcher::kSettleLimitMilliseconds + 100));
    EXPECT_FALSE(files_.changed_since_wait(true)) << "a load was dropped for more than two seconds";
}

// Waiting for an event ends when a look finds nothing to load (the file came back as it was): a
// later unheard change waits for its own event (else it could be read emptied).
TEST_F(FileWatcherTest, ALookThatLoadsNothingEndsTheWaitForAnEvent) {
    EXPECT_FALSE(files_.heard_of_change());
    files_.wait(0);  // the looks after it load nothing and ask nothing
    std::this_thread::sleep_for(std::chrono::milliseconds(FileWatcher::kSettleLimitMilliseconds + 100));
    files_.wait(0);
    EXPECT_FALSE(files_.heard_of_change()) << "an emptied file would be shown";
}

}  // namespace
}  // namespace raycast

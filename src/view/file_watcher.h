// How `raycast view` notices that the scene's files were saved: inotify on their folders, so that a
// save is seen at once, and a look every so often anyway (file systems without inotify, files that
// moved). It only says when to look; the session compares modification times and sizes, and loads.
//
// A save is seldom one step: an editor truncates the file, writes it in one or more pieces and
// closes it, and a writer that loses the processor in between leaves the file empty or half
// written for as long as it waits. Read then, the scene would flash an error and count a version
// of its own. So the watcher waits for writers to finish before it says "look" (wait()), says
// whether a save began while a load read the files (changed_since_wait()), so that such a load
// is dropped rather than shown, and says whether it has heard of the change a look found
// (heard_of_change()): the kernel changes a file a moment before it queues the event, and a look
// in that moment finds an emptied file with no event yet to say that a writer is at work.
#pragma once

#include <chrono>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace raycast {

class FileWatcher {
public:
    /// How long nothing may happen to the watched files before a change counts as finished.
    static constexpr int kQuietMilliseconds = 10;
    /// A writer that keeps changing the files is not waited for longer than this: what it has
    /// written by then is loaded (and loaded again when it is done).
    static constexpr int kSettleLimitMilliseconds = 2000;

    FileWatcher();
    ~FileWatcher();
    FileWatcher(const FileWatcher&) = delete;
    FileWatcher& operator=(const FileWatcher&) = delete;

    /// Whether changes are seen as they happen (inotify); false: only the periodic look.
    bool notified() const { return fd_ >= 0; }

    /// Watches `files` (and forgets files watched before that are not among them). Their folders
    /// are watched once each, and stay watched.
    void watch(const std::vector<std::string>& files);

    /// Returns after `milliseconds` if nothing happened in the watched folders. Otherwise it
    /// returns once every watched file that was written has been closed by its writer (or
    /// replaced by a rename, or deleted) and nothing has happened to the watched files for
    /// kQuietMilliseconds (at once if what happened was to other files), or after
    /// kSettleLimitMilliseconds of changes: then the writers still open are no longer waited for
    /// (a close, when it comes, is a change like any other). A change seen by
    /// changed_since_wait() is waited for here without the `milliseconds`.
    void wait(int milliseconds);

    /// Whether a watched file has changed since wait() returned, so that what was read from the
    /// files since then may be half written. A change is counted once its event is queued, which
    /// the kernel does a moment after the file changed, just before the call that changed it
    /// returns; so the caller says whether it found a file's time or size changed since before
    /// its read (`files_changed`), which counts a save whose first call has not yet returned
    /// (heard_of_change() covers the look before the read). False, so that what was read is shown
    /// all the same, after a wait() that ended at kSettleLimitMilliseconds (a writer that keeps
    /// its file open), and once it has said true for kSettleLimitMilliseconds on end (a writer
    /// that saves again and again, faster than a load): a writer that never stops still gets its
    /// files shown, every two seconds or so. Always false without inotify.
    bool changed_since_wait(bool files_changed = false);

    /// Whether the change that a look after wait() found in the files (their times or sizes) may
    /// be loaded now. True when that wait() read an event about a watched file. Otherwise the
    /// change may be a save caught between its truncation and the truncation's event (the
    /// kernel empties the file first, then queues the event): loaded now, the empty file would
    /// be shown as a version of its own, with an error. So an unheard change waits for its event,
    /// for kSettleLimitMilliseconds at most (then it is loaded: a file system that sends no
    /// events, a folder that could not be watched). Always true without inotify.
    bool heard_of_change();

private:
    using Clock = std::chrono::steady_clock;
    using WatchedName = std::pair<int, std::string>;  // a folder's watch and a name in it

    bool read_events();

    // A run of looks held back (a load dropped, a change waiting for its event), at most
    // kSettleLimitMilliseconds long. A look that does not ask ends the run.
    struct LimitedRun {
        std::optional<Clock::time_point> since;  // held back since
        bool asked = false;                      // hold() was called after the last wait()
        /// Whether to hold this look back: `wanted`, and the run not yet at its limit.
        bool hold(bool wanted);
        /// Called by wait(): a look that did not ask ends the run.
        void new_look();
    };

    int fd_;
    std::vector<std::pair<std::string, int>> folders_;  // each watched folder and its watch (-1: failed)
    std::vector<WatchedName> names_;                    // the watched files
    std::vector<WatchedName> writing_;                  // watched files written and not yet closed
    bool pending_ = false;  // changed_since_wait() saw a change that wait() has not waited for
    bool settled_ = true;   // the last wait() ended with the writers done (not at its limit)
    Clock::time_point last_change_;  // the latest event about a watched file
    LimitedRun dropping_;           // changed_since_wait()'s run of true
    LimitedRun waiting_for_event_;  // heard_of_change()'s run of false
    bool heard_ = false;            // the last wait() read an event about a watched file
};

}  // namespace raycast

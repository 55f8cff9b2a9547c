#include "view/file_watcher.h"

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <thread>

#if __has_include(<sys/inotify.h>)
#include <sys/inotify.h>
#include <unistd.h>
#define RAYCAST_HAVE_INOTIFY 1
#include "view/poll_one.h"
#endif

namespace raycast {

#ifdef RAYCAST_HAVE_INOTIFY

FileWatcher::FileWatcher() : fd_(inotify_init1(IN_NONBLOCK | IN_CLOEXEC)) {}

FileWatcher::~FileWatcher() {
    if (fd_ >= 0) ::close(fd_);
}

void FileWatcher::watch(const std::vector<std::string>& files) {
    if (fd_ < 0) return;
    names_.clear();
    for (const std::string& file : files) {
        const size_t slash = file.find_last_of('/');
        const std::string folder = slash == std::string::npos ? "." : (slash == 0 ? "/" : file.substr(0, slash));
        auto known = std::find_if(folders_.begin(), folders_.end(), [&](const auto& f) { return f.first == folder; });
        if (known == folders_.end()) {
            const int wd = inotify_add_watch(fd_, folder.c_str(),
                                             IN_CLOSE_WRITE | IN_MOVED_TO | IN_CREATE | IN_DELETE | IN_MODIFY);
            known = folders_.insert(folders_.end(), {folder, wd});
        }
        if (known->second >= 0)
            names_.push_back({known->second, slash == std::string::npos ? file : file.substr(slash + 1)});
    }
    // A file no longer watched has no events read any more: waiting for its writer would take
    // every later wait to its limit.
    writing_.erase(std::remove_if(writing_.begin(), writing_.end(),
                                  [&](const WatchedName& name) {
                                      return std::find(names_.begin(), names_.end(), name) == names_.end();
                                  }),
                   writing_.end());
}

void FileWatcher::wait(int milliseconds) {
    // A look that asked nothing (the session found nothing to load, the file came back as it
    // was) ends a run of dropped loads and a wait for an event: the next starts with two seconds
    // of its own.
    dropping_.new_look();
    waiting_for_event_.new_look();
    heard_ = false;
    if (fd_ < 0) {
        std::this_thread::sleep_for(std::chrono::milliseconds(milliseconds));
        return;
    }
    if (!pending_ && (poll_one(fd_, POLLIN, milliseconds) & POLLIN) == 0) {
        settled_ = true;  // nothing written for a while
        return;
    }
    heard_ = pending_;
    pending_ = false;
    settled_ = false;
    const Clock::time_point limit = Clock::now() + std::chrono::milliseconds(kSettleLimitMilliseconds);
    last_change_ = Clock::now();
    for (;;) {
        if (read_events()) heard_ = true;
        const Clock::time_point now = Clock::now();
        if (now >= limit) {
            // Not waited for any more. A name created without a writer (a link) never closes,
            // and kept here it would take every later wait to its limit.
            writing_.clear();
            return;
        }
        // With no watched file open for writing, done once none has changed for a moment (other
        // files in the folders, an editor's swap file, do not count); else wait for the writers.
        Clock::time_point until = limit;
        if (writing_.empty()) {
            until = last_change_ + std::chrono::milliseconds(kQuietMilliseconds);
            if (now >= until) {
                settled_ = true;
                return;
            }
        }
        poll_one(fd_, POLLIN, static_cast<int>(std::chrono::ceil<std::chrono::milliseconds>(until - now).count()));
    }
}

bool FileWatcher::LimitedRun::hold(bool wanted) {
    asked = true;
    if (wanted) {
        const Clock::time_point now = Clock::now();
        if (!since) since = now;
        if (now - *since < std::chrono::milliseconds(kSettleLimitMilliseconds)) return true;
    }
    since.reset();
    return false;
}

void FileWatcher::LimitedRun::new_look() {
    if (!asked) since.reset();
    asked = false;
}

bool FileWatcher::changed_since_wait(bool files_changed) {
    if (fd_ < 0) return false;
    if (read_events()) pending_ = true;
    // A change found by its time or size alone does not make the next wait() skip its look: its
    // event is still to come, and that wait() waits for it.
    return dropping_.hold((pending_ || files_changed) && settled_);  // false: what was read is shown
}

bool FileWatcher::heard_of_change() {
    if (fd_ < 0) return true;
    return !waiting_for_event_.hold(!heard_);
}

// Reads the pending events, keeping in writing_ the watched files that are being written and in
// last_change_ the time of the latest event about one. Returns whether any event was about a
// watched file.
bool FileWatcher::read_events() {
    alignas(inotify_event) char buffer[4096];
    bool watched = false;
    for (;;) {
        const ssize_t length = ::read(fd_, buffer, sizeof buffer);
        if (length <= 0) break;
        for (ssize_t at = 0; at + static_cast<ssize_t>(sizeof(inotify_event)) <= length;) {
            inotify_event event;
            std::memcpy(&event, buffer + at, sizeof event);
            const char* name = buffer + at + sizeof event;
            at += static_cast<ssize_t>(sizeof event + event.len);
            if (event.mask & IN_Q_OVERFLOW) {
                // Events were lost: any watched file may have changed, and any writer closed.
                writing_.clear();
                watched = true;
                continue;
            }
            if (event.len == 0 || at > length) continue;
            const WatchedName key{event.wd, std::string(name, strnlen(name, event.len))};
            if (std::find(names_.begin(), names_.end(), key) == names_.end()) continue;
            watched = true;
            const auto open = std::find(writing_.begin(), writing_.end(), key);
            const bool done = (event.mask & (IN_CLOSE_WRITE | IN_MOVED_TO | IN_DELETE)) != 0;
            if (done && open != writing_.end()) writing_.erase(open);
            if (!done && (event.mask & (IN_MODIFY | IN_CREATE)) && open == writing_.end()) writing_.push_back(key);
        }
    }
    if (watched) last_change_ = Clock::now();
    return watched;
}

#else  // no inotify: only the periodic look

FileWatcher::FileWatcher() : fd_(-1) {}
FileWatcher::~FileWatcher() = default;
void FileWatcher::watch(const std::vector<std::string>&) {}
void FileWatcher::wait(int milliseconds) { std::this_thread::sleep_for(std::chrono::milliseconds(milliseconds)); }
bool FileWatcher::changed_since_wait(bool) { return false; }
bool FileWatcher::heard_of_change() { return true; }
bool FileWatcher::read_events() { return false; }

#endif

}  // namespace raycast

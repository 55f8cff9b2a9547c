// One descriptor's poll(), shared by the viewer's socket waits (view_server.cpp) and its file
// watcher's inotify waits (file_watcher.cpp). Each caller rounds its own deadline to
// milliseconds: the server down (a request's budget is never overrun), the watcher up (it never
// spins through the last millisecond before a deadline).
#pragma once

#include <poll.h>

#include <algorithm>
#include <cerrno>

namespace raycast {

/// Waits up to `milliseconds` (0 or less: only what is there now) for `events` on `fd`, and
/// returns what poll() reported (revents: the events that came, and POLLHUP, POLLERR or POLLNVAL
/// where those apply), or 0 when nothing came in time or poll() failed. A signal that interrupts
/// the wait starts it again.
inline short poll_one(int fd, short events, int milliseconds) {
    pollfd watched{fd, events, 0};
    for (;;) {
        const int ready = ::poll(&watched, 1, std::max(milliseconds, 0));
        if (ready < 0 && errno == EINTR) continue;
        return ready > 0 ? watched.revents : 0;
    }
}

}  // namespace raycast

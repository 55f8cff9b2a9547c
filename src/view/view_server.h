// `raycast view`: the live viewer's HTTP server (cpp-httplib, when the build found it). It serves
// the page and the three endpoints of ViewSession on one address, reloads the scene when its files
// change, and runs until SIGINT or SIGTERM.
#pragma once

#include <functional>
#include <string>

#include "view/file_watcher.h"
#include "view/view_session.h"

namespace raycast {

struct ViewServerOptions {
    std::string host = "127.0.0.1";  ///< loopback unless the user says otherwise
    int port = 0;                    ///< 0: any free port
};

/// Whether this build has the HTTP server (cpp-httplib was found).
bool view_server_available();

/// Serves `session` until SIGINT or SIGTERM, reloading it when `files` (watching its scene file
/// since before its first load, so that no save is missed) sees a change. Calls `listening` with
/// the page's URL once the port is open. Throws InputError when the address cannot be used.
void run_view_server(ViewSession& session, FileWatcher& files, const ViewServerOptions& options,
                     const std::function<void(const std::string& url)>& listening);

}  // namespace raycast

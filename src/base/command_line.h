// Small helpers for the command lines of raycast's tools (raycast_revolve, raycast_meshgen), so
// that they read their arguments as raycast itself and GNU tools do.
#pragma once

#include <string>
#include <vector>

namespace raycast {

/// argv[1..argc) with every "--name=value" split into "--name" and "value" ("--along=8" reads as
/// "--along 8"); everything else as it is.
inline std::vector<std::string> split_attached_values(int argc, const char* const* argv) {
    std::vector<std::string> args;
    for (int i = 1; i < argc; ++i) {
        const std::string arg = argv[i];
        const size_t equals = arg.find('=');
        if (arg.rfind("--", 0) == 0 && equals != std::string::npos && equals > 2) {
            args.push_back(arg.substr(0, equals));
            args.push_back(arg.substr(equals + 1));
        } else {
            args.push_back(arg);
        }
    }
    return args;
}

/// Whether the arguments ask for help (-h or --help anywhere): the usage goes to standard output
/// and the tool exits 0, as raycast --help does.
inline bool asks_for_help(const std::vector<std::string>& args) {
    for (const std::string& arg : args)
        if (arg == "-h" || arg == "--help") return true;
    return false;
}

}  // namespace raycast

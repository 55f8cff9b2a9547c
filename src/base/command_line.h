// Small helpers for command lines: raycast's tools (raycast_revolve, raycast_meshgen) read their
// arguments with them as raycast itself (cli/cli_options.cpp) and GNU tools do.
#pragma once

#include <string>
#include <vector>

namespace raycast {

/// Whether `arg` is "--name=value" with a name: then `name` is "--name" and `value` what follows
/// the first '=' (perhaps empty). raycast's own parser and its tools' split alike.
inline bool split_long_option(const std::string& arg, std::string& name, std::string& value) {
    const size_t equals = arg.find('=');
    if (arg.rfind("--", 0) != 0 || equals == std::string::npos || equals <= 2) return false;
    name = arg.substr(0, equals);
    value = arg.substr(equals + 1);
    return true;
}

/// argv[1..argc) with every "--name=value" split into "--name" and "value" ("--along=8" reads as
/// "--along 8"); everything else as it is.
inline std::vector<std::string> split_attached_values(int argc, const char* const* argv) {
    std::vector<std::string> args;
    for (int i = 1; i < argc; ++i) {
        const std::string arg = argv[i];
        std::string name, value;
        if (split_long_option(arg, name, value)) {
            args.push_back(name);
            args.push_back(value);
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

#pragma once
// Outputs are written to a temporary file beside the target and renamed into place only when
// complete, so a failure never leaves a partial file under the requested name. The temporary
// lives in its own hidden directory, removed with everything in it on an exception and, through
// a signal handler installed on first use (only where the action is the default), on SIGINT,
// SIGTERM and SIGHUP, after which the signal is re-raised.
#include <functional>
#include <string>
#include <vector>

namespace glintscope {

// Calls write(temporary_path); on success renames it to `path`, on any exception removes it
// and rethrows. Throws Error if the target directory does not exist.
void write_atomically(const std::string& path, const std::function<void(const std::string&)>& write);

// Checks, before any work, that `path` can be written: its extension is one of `extensions`
// (lower case, without the dot), its directory exists and is writable, and it is not a
// directory. Throws Error naming `what` ("-o", "--png", ...) and the problem.
void check_output_path(const std::string& path, const std::vector<std::string>& extensions, const std::string& what);

// Writes `text` to `path` atomically (CSV, JSON, reports).
void write_text_file(const std::string& path, const std::string& text);

// The lower-case extension of a path without the dot ("exr", "x3p", ...).
std::string file_extension(const std::string& path);

}  // namespace glintscope

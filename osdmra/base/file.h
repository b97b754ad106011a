// Files written all at once or not at all: every file osdmra writes (meshes, .mra
// files, the command-line tool's tables) goes through here.
//
// The data goes to a temporary file created exclusively next to the target, is
// flushed to disk (fsync), and is then renamed over the target; rename() within one
// directory is atomic, so readers see either the old file or the complete new one,
// and an interrupted or failed write leaves the target as it was.
#pragma once

#include <functional>
#include <ostream>
#include <string>

namespace osdmra {

/// Calls `write` with a binary stream on a temporary file next to `path`, then
/// replaces `path` with it. If `write` throws, or the stream fails, or the file
/// cannot be created, synced or renamed, the temporary file is removed and `path` is
/// untouched. Failures of the file are an Error that starts with `path`; an Error
/// from `write` that does not name `path` gets it as a prefix; any other exception
/// from `write` passes through unchanged (after the clean-up).
void writeFileAtomically(const std::string& path, const std::function<void(std::ostream&)>& write);

/// A text file (an exact copy of `text`), written as above.
void writeTextFile(const std::string& path, const std::string& text);

}  // namespace osdmra

// Text from a scene or the command line, shown to a person in a message, a summary, a progress
// bar or a window title: one line of readable length, whatever the text holds.
#pragma once

#include <cstddef>
#include <string>

namespace drape::io {

/// `text` with control characters (newlines and terminal escapes among them) and invalid UTF-8
/// bytes replaced by '?', cut to `max_chars` characters with "..." when longer.
std::string shown(const std::string& text, size_t max_chars = 60);

}  // namespace drape::io

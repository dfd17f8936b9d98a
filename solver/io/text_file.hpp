#pragma once
// Small files written whole or not at all, with every write checked: a full disk or
// an unwritable directory is an Error naming the file, never a silently short file.
#include <string>

namespace narwhal {

// Writes `content` to a temporary file beside `path`, flushes it to disk, then
// renames it over `path`; a reader sees the old file or the new one, never a part.
void write_file_atomically(const std::string& path, const std::string& content);

// The whole content of a regular text file (an Error naming it if it is not one or cannot be read).
std::string read_text_file(const std::string& path);

}  // namespace narwhal

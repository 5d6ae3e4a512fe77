#pragma once
// Every file shearbench writes goes through here: the bytes go to a hidden temporary in the target's
// folder (".<name>.tmp.<pid>"), are flushed, and the temporary is renamed over the target. A reader,
// or a user's old file, therefore never sees a half-written file: a crash or kill leaves either the old
// file or the new one (plus, at worst, a hidden temporary no reader looks at).
#include <string>
#include <string_view>

namespace sb {

// Writes `content` to `path` atomically; creates missing parent folders. Throws InputError naming
// the path when the folder is not writable, the disk is full or the rename fails (the temporary is
// removed then and the old file left untouched).
void write_file_atomic(const std::string& path, std::string_view content);

// Encodes an 8-bit image (BGR or grey, OpenCV layout) as PNG and writes it atomically.
// `data` is rows*cols*channels bytes, row-major, no padding.
void write_png_atomic(const std::string& path, int rows, int cols, int channels, const unsigned char* data);

// The hidden temporary write_file_atomic uses for `path` (for tests and for readers that skip them).
std::string atomic_temporary_path(const std::string& path);

}  // namespace sb

#pragma once

#include "base/expected.h"

#include <cstdint>
#include <span>
#include <string>

namespace dc::base {

// Writes every byte of both spans (one writev, retried on EINTR and short writes); 0 or -errno.
int writeAll(int fd, std::span<const std::uint8_t> first, std::span<const std::uint8_t> second = {});

// Replaces `path` with `bytes` so that a reader, a crash or a power cut sees either the old file or the new
// one, never a part: written to a temporary file beside it, flushed to disk, renamed over, and the directory
// flushed so the rename itself survives.
Status writeFileAtomically(const std::string& path, std::span<const std::uint8_t> bytes);
Status writeTextFile(const std::string& path, const std::string& text);

} // namespace dc::base

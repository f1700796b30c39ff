#pragma once

#include "base/expected.h"

#include <cstdint>
#include <functional>
#include <span>
#include <string>
#include <vector>

namespace dc::base {

// Writes every byte of both spans (one writev, retried on EINTR and short writes); 0 or -errno.
int writeAll(int fd, std::span<const std::uint8_t> first, std::span<const std::uint8_t> second = {});

// The steps of writeFileAtomically, in order.
enum class AtomicWriteStep { Open, Write, Sync, Rename, SyncDirectory };

// The fault-injection seam of writeFileAtomically: called before each step with its name, a negative
// errno makes that step fail as if its system call had returned it (0: the step runs for real).
using AtomicWriteFault = std::function<int(AtomicWriteStep)>;

// Replaces `path` with `bytes` so that a reader, a crash or a power cut sees either the old file or the new
// one, never a part: written to a temporary file beside it, flushed to disk, renamed over, and the directory
// flushed so the rename itself survives. A failure before the rename leaves the old file as it was; after
// it (flushing the directory), the new file is whole in its place but may not survive a power cut. Either
// way no temporary file is left behind.
Status writeFileAtomically(const std::string& path, std::span<const std::uint8_t> bytes,
                           const AtomicWriteFault& fault = {});
Status writeTextFile(const std::string& path, const std::string& text);
// Renames `from` to `to`; unless `overwrite`, an existing `to` is not replaced (RENAME_NOREPLACE, or link()
// where the filesystem refuses the flag), so the existence check made when `from` was created holds at the
// rename too. An existing `to` is the error `existsMessage`; another failure names both paths.
Status renameInto(const std::string& from, const std::string& to, bool overwrite,
                  const std::string& existsMessage);
// Every byte of a file; an error names the file and the reason.
Expected<std::vector<std::uint8_t>> readFile(const std::string& path);

// Creates a directory under `parent` (made first if missing) that did not exist before: `stem`, else
// `stem-2`, `stem-3`, … Creation is exclusive, so two savers never share one. Returns its path.
Expected<std::string> createFreshDirectory(const std::string& parent, const std::string& stem);

} // namespace dc::base

// SPDX-License-Identifier: Apache-2.0
#pragma once
/// \file file_io.h
/// The one guarded way MorphMill reads and writes whole files.
///
/// Reading accepts regular files only: a FIFO, a device (/dev/zero), a socket or a directory is
/// refused by name without blocking and without reading a byte, and the file's real length is
/// checked against a cap before anything is allocated. Writing goes to a temporary file in the
/// target's directory, checked (a short write or ENOSPC is an error), flushed to disk and renamed
/// over the target, so a target is always either its old content or the complete new one.
#include <cstdint>
#include <string>
#include <string_view>

namespace morph {

/// Default cap on the size of one input file: 4 GiB.
inline constexpr std::uint64_t kDefaultMaxInputBytes = std::uint64_t(4) << 30;

/// The whole content of the regular file `path`. `what` names the file's role in messages
/// ("job file", "G-code file", "mesh"). Throws InputError when `path` is not a regular file or is
/// longer than `max_bytes`, IoError when it cannot be opened or read.
std::string read_regular_file(const std::string& path, std::string_view what,
                              std::uint64_t max_bytes = kDefaultMaxInputBytes);

/// Replaces `path` with `bytes` atomically (temporary file in the same directory, fsync, rename).
/// A symbolic link is followed and the file it names is replaced. When `path` exists and is not a
/// regular file (a FIFO, /dev/null, /dev/full, /dev/stdout) the bytes are written into it directly,
/// every write checked. Throws IoError naming `path` and the system's reason.
void write_file_atomically(const std::string& path, std::string_view bytes);

}  // namespace morph

// SPDX-License-Identifier: Apache-2.0
#pragma once
// Small pieces shared by the self-contained HTML reports of verify and study.
#include <filesystem>
#include <string>

namespace morphmill {

/// The whole file as bytes; throws morph::IoError naming it if it cannot be read.
std::string read_file_bytes(const std::filesystem::path& path);
/// Standard base64 with padding (for data: URIs).
std::string base64(const std::string& bytes);
/// Escapes &, <, > and " for HTML text and attribute values.
std::string html_escape(const std::string& text);

}  // namespace morphmill

#pragma once
namespace shellflow {
/// Project version, from CMake's project().
inline constexpr const char* version = SHELLFLOW_VERSION;
/// Source tree the binary was built from (to find cases and tools by default).
inline constexpr const char* source_dir = SHELLFLOW_SOURCE_DIR;
}  // namespace shellflow

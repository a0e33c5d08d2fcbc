#pragma once
namespace shellflow {
/// Project version, from CMake's project().
inline constexpr const char* version = SHELLFLOW_VERSION;
/// Source tree the binary was built from (to find cases and tools by default). Defined in
/// version.cpp alone, so that no other object depends on where the tree lies (ccache hits
/// across checkouts).
extern const char* const source_dir;
}  // namespace shellflow

#pragma once
// Checkpoint files (docs/restart.md): everything the next step of a run reads, in one binary
// file per checkpoint, `OUTDIR/checkpoint_NNNNNN.ckpt` (NNNNNN: the step).
//
//   "shellflow checkpoint\n"                 magic (21 bytes)
//   u32 format                               kCheckpointFormat
//   u64 header bytes, u64 payload bytes, u64 checksum (checksum64 of the payload, seeded with
//                                            checksum64 of the header)
//   header (core/archive.h): program version, build id, case name, step, time, threads,
//          element-pass instruction set, the case's section digests
//   payload: the run's state (the run driver's, the solvers', the output writers')
//
// A checkpoint is written to `<name>.tmp`, flushed to disk (fsync) and renamed, so a file
// named checkpoint_NNNNNN.ckpt is always complete; the previous checkpoint is removed only
// after that (the two newest are kept). A damaged or truncated file fails its checksum or
// its sizes.
#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "shellflow/core/archive.h"

namespace YAML {
class Node;
}

namespace shellflow::mesh {
struct Mesh;
}

namespace shellflow::io {

inline constexpr std::uint32_t kCheckpointFormat = 3;  // 2: the instruction set in the header; 3: coupling iterations

/// A named digest of one part of a run's input: a top-level section of the case file
/// ("shell", "fluid", ...) or a mesh ("mesh fluid").
struct SectionDigest {
  std::string name;
  std::uint64_t digest = 0;
  bool operator==(const SectionDigest&) const = default;
};

/// The digests of a case file's top-level sections (after --set overrides), each over the
/// section's YAML as yaml-cpp emits it. Left out, because a restart may change them:
/// `study` (run ignores it), `output.directory`, `output.checkpoint_every` and `time.end`
/// (a restarted run may be continued further).
std::vector<SectionDigest> case_digests(const YAML::Node& root);
/// The digest of a mesh's nodes, cells and physical groups.
SectionDigest mesh_digest(const mesh::Mesh& m);

struct CheckpointHeader {
  std::string program_version;  ///< shellflow::version
  std::uint64_t build = 0;      ///< checksum of the executable that wrote it (0: unknown)
  std::string case_name;
  long step = 0;
  double time = 0.0;
  int threads = 1;   ///< OpenMP threads of the run
  std::string simd;  ///< the element pass's instruction set (fluid::SimdPath)
  std::vector<SectionDigest> digests;
};

struct Checkpoint {
  std::filesystem::path file;
  CheckpointHeader header;
  std::string payload;
};

/// `dir/checkpoint_NNNNNN.ckpt` of step `step`.
std::filesystem::path checkpoint_path(const std::filesystem::path& dir, long step);
/// Whether `name` is a checkpoint file name (or the .tmp of one).
bool is_checkpoint_name(std::string_view name);

/// Writes the checkpoint (tmp + fsync + rename), then removes the older checkpoints of `dir`
/// but the newest other one. Returns the file's size in bytes. Throws Error when it cannot
/// be written (the previous checkpoints are then kept).
std::uint64_t write_checkpoint(const std::filesystem::path& dir, const CheckpointHeader& header,
                               std::string_view payload);

/// Reads and verifies a checkpoint: one-line Error for a missing file, one that is not a
/// checkpoint, of another format, truncated, or damaged (checksum).
Checkpoint read_checkpoint(const std::filesystem::path& file);

/// read_checkpoint's checks on the bytes of a whole file in memory (`file` names it in the
/// messages; its name's step is compared with the header's). The fuzz target's entry.
Checkpoint parse_checkpoint(std::string_view bytes, const std::filesystem::path& file);

/// `path` as given to --restart: a checkpoint file, or an output directory (its newest
/// complete checkpoint). Throws Error when there is none.
std::filesystem::path find_checkpoint(const std::filesystem::path& path);

/// The checksum of the running executable (/proc/self/exe), computed once; 0 when it cannot
/// be read.
std::uint64_t executable_build_id();

/// Why a checkpoint cannot continue this run, or empty when it can: another program
/// version, another case (the sections that differ, by name), other meshes. `file` names
/// the checkpoint in the message.
std::string checkpoint_mismatch(const Checkpoint& checkpoint, const CheckpointHeader& current);

}  // namespace shellflow::io

#pragma once
// ParaView data collection (`.pvd`): the list of `.vtu` files of one output series with
// their times. ParaView opens the `.pvd` and shows the series as one time-dependent
// dataset.
//
//   <?xml version="1.0"?>
//   <VTKFile type="Collection" version="0.1" byte_order="LittleEndian">
//     <Collection>
//       <DataSet timestep="0.001" group="" part="0" file="fluid/fluid_000001.vtu"/>
//       ...
//     </Collection>
//   </VTKFile>
//
// The whole file is rewritten (through `<file>.tmp` and a rename) at construction and
// after every `add`, so it is always complete, valid XML: a run that dies leaves a
// collection of everything written so far.
#include <filesystem>
#include <string>
#include <vector>

#include "shellflow/core/archive.h"
#include "shellflow/io/probe_writer.h"

namespace shellflow::io {

class PvdWriter {
 public:
  /// One dataset of the collection.
  struct Entry {
    double time = 0;
    std::string file;  ///< relative to the `.pvd`'s directory
    int part = 0;
  };

  /// Starts the collection `<dir>/<basename>.pvd` (creating `dir`), writing it empty;
  /// an existing file of that name is replaced. Throws shellflow::InputError for an empty
  /// basename or one containing a path separator, shellflow::Error when the file cannot be
  /// written. With OutputMode::resume nothing is written until restore().
  PvdWriter(std::filesystem::path dir, std::string basename, OutputMode mode = OutputMode::create);

  /// Checkpoint: the entries. restore() rewrites the `.pvd` with them (the frames written
  /// after the checkpoint leave the collection; they are added again).
  void save(ArchiveWriter& out) const;
  void restore(ArchiveReader& in);

  /// Adds dataset `vtu_relative_path` (relative to `dir`, '/' separated) at `time`, as
  /// part `part` of that time step (several parts per step become the blocks of a
  /// multiblock dataset in ParaView), then rewrites the `.pvd`. An entry with the same
  /// time and part is replaced. Throws shellflow::Error for a non-finite time, a
  /// negative part, an empty or absolute path, or a write failure.
  void add(double time, const std::string& vtu_relative_path, int part = 0);

  /// The `.pvd` file's path.
  const std::filesystem::path& path() const { return path_; }
  const std::vector<Entry>& entries() const { return entries_; }

 private:
  void write() const;
  std::string xml() const;  ///< the .pvd file of entries_

  std::filesystem::path path_;
  std::vector<Entry> entries_;
};

}  // namespace shellflow::io

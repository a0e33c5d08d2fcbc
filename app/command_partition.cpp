// `shellflow partition`: split a case's fluid mesh into parts (METIS) and report the parts'
// sizes, ghost layers and exchange lists as the distributed flow would hold them.
#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <CLI/CLI.hpp>
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include "commands.h"
#include "shellflow/core/error.h"
#include "shellflow/core/json.h"
#include "shellflow/core/output_file.h"
#include "shellflow/io/case_meshes.h"
#include "shellflow/io/vtu_writer.h"
#include "shellflow/mesh/partition.h"

namespace shellflow::app {

namespace {

std::string stats_to_json(const mesh::Mesh& m, const mesh::PartitionStats& s) {
  std::string out = "{\n";
  out += fmt::format("  \"mesh\": {},\n  \"source\": {},\n", json_string(m.name), json_string(m.source));
  out += fmt::format(
      "  \"parts\": {},\n  \"nodes\": {},\n  \"cells\": {},\n  \"ghost_nodes\": {},\n  \"ghost_cells\": {},\n"
      "  \"interface_nodes\": {},\n  \"imbalance\": {},\n  \"work_imbalance\": {},\n"
      "  \"max_halo_share\": {},\n  \"mean_halo_share\": {},\n  \"per_part\": [\n",
      s.parts.size(), s.nodes, s.cells, s.ghost_nodes, s.ghost_cells, s.interface_nodes, json_number(s.imbalance),
      json_number(s.work_imbalance), json_number(s.max_halo_share), json_number(s.mean_halo_share));
  for (std::size_t r = 0; r < s.parts.size(); ++r) {
    const mesh::PartStats& p = s.parts[r];
    out += fmt::format(
        "    {{\"rank\": {}, \"owned_nodes\": {}, \"ghost_nodes\": {}, \"owned_cells\": {}, \"ghost_cells\": {}, "
        "\"local_cells\": {}, \"neighbours\": {}, \"interface_nodes\": {}, \"halo_share\": {}}}{}\n",
        r, p.owned_nodes, p.ghost_nodes, p.owned_cells, p.ghost_cells, p.local_cells, p.neighbours, p.interface_nodes,
        json_number(p.halo_share), r + 1 < s.parts.size() ? "," : "");
  }
  out += "  ]\n}\n";
  return out;
}

}  // namespace

int partition_command(const CommonOptions& options, int parts) {
  const io::Case c = read_case(options);
  if (!c.meshes.fluid) {
    throw_input_error("{}: the case has no fluid mesh to partition (meshes.fluid)", options.case_file.string());
  }
  const auto folder = prepare_output_dir(c, options);  // locked while this command runs
  const std::filesystem::path& outdir = folder.path;
  spdlog::info("partitioning the fluid mesh of {} into {} parts in {}", options.case_file.string(), parts,
               outdir.string());
  const io::CaseMeshes meshes = io::load_case_meshes(c, outdir);
  const mesh::Mesh& fluid = *meshes.fluid;

  const std::vector<int> cell_part = mesh::partition_cells(fluid, parts);
  const std::vector<int> owner = mesh::node_owners(fluid, cell_part);
  const mesh::PartitionStats stats = mesh::partition_stats(fluid, cell_part, owner);

  write_file_atomically(outdir / "partition.json", stats_to_json(fluid, stats));
  // The writer holds Float64 fields: the integer ranks are exact in them.
  const std::vector<double> rank(cell_part.begin(), cell_part.end());
  const std::vector<double> node_owner(owner.begin(), owner.end());
  io::VtuGrid grid;
  grid.points = io::flat(fluid.nodes);
  grid.cells.push_back({static_cast<int>(fluid.cells.type), fluid.cells.connectivity});
  grid.point_fields.push_back({"owner", 1, node_owner});
  grid.cell_fields.push_back({"rank", 1, rank});
  io::write_vtu(outdir / "partition.vtu", grid);

  fmt::print("{:>4} {:>8} {:>7} {:>8} {:>7} {:>5} {:>9} {:>6}\n", "part", "nodes", "ghosts", "cells", "g.cells", "nbrs",
             "interface", "halo");
  for (std::size_t r = 0; r < stats.parts.size(); ++r) {
    const mesh::PartStats& p = stats.parts[r];
    fmt::print("{:>4} {:>8} {:>7} {:>8} {:>7} {:>5} {:>9} {:>6.3f}\n", r, p.owned_nodes, p.ghost_nodes, p.owned_cells,
               p.ghost_cells, p.neighbours, p.interface_nodes, p.halo_share);
  }
  fmt::print("{:>4} {:>8} {:>7} {:>8} {:>7} {:>5} {:>9} {:>6.3f}\n", "all", stats.nodes, stats.ghost_nodes, stats.cells,
             stats.ghost_cells, "", stats.interface_nodes, stats.mean_halo_share);
  fmt::print(
      "imbalance {:.3f} (max owned cells / mean; with the ghost layer {:.3f}), halo share max {:.3f} mean {:.3f}\n",
      stats.imbalance, stats.work_imbalance, stats.max_halo_share, stats.mean_halo_share);
  std::fflush(stdout);
  spdlog::info("wrote {}: partition.json, partition.vtu", outdir.string());
  return 0;
}

Command add_partition_command(CLI::App& cli, CommonOptions& common) {
  auto parts = std::make_shared<int>(0);
  auto* sub = cli.add_subcommand("partition",
                                 "Split the case's fluid mesh into parts (METIS) as a distributed run would: "
                                 "print each part's owned and ghost nodes and cells, neighbours and interface "
                                 "nodes, the halo share and the imbalance; write partition.json and "
                                 "partition.vtu (cell field rank, point field owner)");
  add_case_options(sub, common);
  sub->add_option("-o,--output", common.output_dir,
                  "Output directory (default: the case's output.directory, else out/<name>)");
  sub->add_option("--parts", *parts, "Number of parts (ranks)")->required()->check(CLI::Range(1, 1 << 24));
  return {sub, [&common, parts] { return partition_command(common, *parts); }};
}

}  // namespace shellflow::app

#include "shellflow/run/recorder.h"

#include <algorithm>
#include <chrono>

namespace shellflow::run {

Recorder::Recorder(const io::Case& c, const io::CaseMeshes& meshes, const std::filesystem::path& outdir,
                   io::OutputMode mode)
    : probes_(c.probes, meshes, outdir / "probes.csv", mode) {
  for (const mesh::Mesh* m : meshes.all()) initial_.push_back(std::make_unique<InitialOutput>(c, *m, outdir));
}

void Recorder::add(MeshOutput& output) {
  std::erase_if(initial_, [&](const auto& o) { return o->key() == output.key(); });
  outputs_.push_back(&output);
}

void Recorder::register_outputs(RunControl& control) {
  control.add_output(probes_.writer());
  for (MeshOutput* o : outputs_) control.add_output(o->pvd());
  for (io::ProbeWriter* csv : csvs_) control.add_output(*csv);
}

std::vector<io::FieldView> Recorder::views() const {
  std::vector<io::FieldView> views;
  for (const MeshOutput* o : outputs_) std::ranges::move(o->views(), std::back_inserter(views));
  for (const auto& o : initial_) std::ranges::move(o->views(), std::back_inserter(views));
  return views;
}

void Recorder::record(long step, double t, Record what) {
  const auto start = std::chrono::steady_clock::now();
  struct AddTime {
    double& sum;
    std::chrono::steady_clock::time_point start;
    ~AddTime() { sum += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(); }
  } add_time{seconds_, start};
  if (what != Record::fields) {
    for (MeshOutput* o : outputs_) o->prepare_sample();
    const std::vector<double> values = probes_.record(t, views());
    if (on_sample_) on_sample_(t, values);
  }
  if (what == Record::probes) return;
  for (MeshOutput* o : outputs_) o->write(step, t);
  // The meshes no solver moves keep their initial state: frame 0 only.
  if (step == 0)
    for (const auto& o : initial_) o->write(0, t);
}

}  // namespace shellflow::run

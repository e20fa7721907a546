// spinewatch fit-cvsm: the CVSM template fitted to a reference subject
// rendered by the phantom at known poses (how config/cvsm-generic.toml is
// made from config/subjects/generic.json; docs/cvsm.md).
#include <algorithm>
#include <memory>

#include <spdlog/spdlog.h>

#include "command.hpp"
#include "output_file.hpp"
#include "spinewatch/estimator/cvsm/template_fit.hpp"
#include "spinewatch/estimator/silhouette/silhouette.hpp"
#include "spinewatch/frames/text_file.hpp"
#include "spinewatch/phantom/phantom.hpp"

namespace spinewatch::cli {
namespace {

LumaView luma_of(const cv::Mat& m) { return {m.data, m.cols, m.rows, static_cast<std::ptrdiff_t>(m.step), 1}; }

// Neutral frames of the reference subject: quiet standing (sway only, so
// the true L5 carries the pose) and the first, still upright, frames of
// the seated scenario. Silhouettes come from the same extractor the
// daemon runs, learnt from the scenario's empty frames.
Result<std::vector<TemplateSample>> render_samples(const phantom::Subject& subject) {
  struct Take {
    const char* scenario;
    std::vector<int> frames;  // person frames
    SubjectPosture posture;
  };
  const Take takes[] = {{"upright", {0, 20, 40, 60}, SubjectPosture::Standing},
                        {"seated_flexion", {0, 1}, SubjectPosture::Seated}};
  std::vector<TemplateSample> samples;
  for (const Take& take : takes) {
    phantom::PhantomOptions po;
    po.scenario = take.scenario;
    po.subject = subject;
    po.frames = 66;
    po.seed = 3;
    auto seq = phantom::PhantomSequence::create(po);
    if (!seq) return seq.error();
    SilhouetteExtractor frontal{SilhouetteOptions{}}, lateral{SilhouetteOptions{}};
    for (int i = 0; i < seq->frame_count(); ++i) {
      const phantom::PhantomFrame f = seq->render(i);
      const SilhouetteResult sf = frontal.extract(luma_of(f.luma[0]));
      const SilhouetteResult sl = lateral.extract(luma_of(f.luma[1]));
      const int person = i - po.empty_frames;
      if (std::find(take.frames.begin(), take.frames.end(), person) == take.frames.end()) continue;
      if (sf.status != SilhouetteStatus::Person || sl.status != SilhouetteStatus::Person || !f.truth.vertebrae)
        return Error{fmt::format("{} frame {}: no clean silhouette of the subject", take.scenario, person)};
      samples.push_back({sf.mask, sl.mask, take.posture, subject.height_mm, (*f.truth.vertebrae)[kWaistIndex].body_center});
    }
  }
  return samples;
}

int run_fit(const std::string& subject_path, const std::string& model_path, const std::string& out_path) {
  auto subject = subject_path.empty() ? Result<phantom::Subject>(phantom::Subject{}) : phantom::load_subject(subject_path);
  if (!subject) {
    spdlog::error("{}", subject.error().message);
    return 1;
  }
  std::string text(generic_cvsm_toml());
  if (!model_path.empty()) {
    auto file = read_text_file(model_path);
    if (!file) {
      spdlog::error("{}", file.error().message);
      return 1;
    }
    text = std::move(file).value();
  }
  auto start = parse_cvsm_spec(text, model_path.empty() ? "config/cvsm-generic.toml" : model_path);
  if (!start) {
    spdlog::error("{}", start.error().message);
    return 1;
  }
  auto samples = render_samples(*subject);
  if (!samples) {
    spdlog::error("{}", samples.error().message);
    return 1;
  }
  const TemplateFit fit = fit_cvsm_template(CameraRig::default_rig(), *start, *samples);
  spdlog::info("fit-cvsm: {} frame pairs, XOR {} → {} px ({} evaluations)", samples->size(), fit.xor_before,
               fit.xor_after, fit.evaluations);
  if (auto written = write_output(out_path, rewrite_cvsm_values(text, fit.spec)); !written) {
    spdlog::error("{}", written.error().message);
    return 1;
  }
  return 0;
}

}  // namespace

void add_fit_cvsm_command(CLI::App& app, ExitCode& exit_code) {
  struct Options {
    std::string subject, model, out;
  };
  auto opts = std::make_shared<Options>();
  auto* cmd = app.add_subcommand("fit-cvsm", "Fit the CVSM template to a reference subject rendered at known poses");
  cmd->add_option("--subject", opts->subject, "reference SUBJECT.json (default: the generic adult)");
  cmd->add_option("--model", opts->model, "template to start from (default: the built-in config/cvsm-generic.toml)");
  cmd->add_option("--out", opts->out, "template TOML to write (comments kept)")->required();
  cmd->callback([opts, &exit_code] { exit_code.value = run_fit(opts->subject, opts->model, opts->out); });
}

}  // namespace spinewatch::cli

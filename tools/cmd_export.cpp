// spinewatch export: the vertebra poses of a time range as OpenSim motion
// and marker files (docs/exposure.md, "Export for researchers"):
// DIR/spine.mot and DIR/spine.trc, from the station's database or a
// posture stream file.
#include <filesystem>
#include <memory>

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include "command.hpp"
#include "output_file.hpp"
#include "spinewatch/daemon/stored_lines.hpp"
#include "spinewatch/export/opensim_files.hpp"
#include "spinewatch/export/posture_rows.hpp"
#include "spinewatch/report/summary_set.hpp"

namespace spinewatch::cli {

void add_export_command(CLI::App& app, ExitCode& exit_code) {
  struct Options {
    std::string db, postures, from, to, out;
  };
  auto opts = std::make_shared<Options>();
  auto* cmd = app.add_subcommand("export", "Vertebra poses of a time range as OpenSim files (spine.mot, spine.trc)");
  auto* db = cmd->add_option("--db", opts->db, "the station's database ([storage] path; postures as stored, every "
                                               "storage.posture_every-th)");
  auto* file = cmd->add_option("--postures", opts->postures, "a posture stream (replay --out, a recorded stream)");
  db->excludes(file);
  cmd->add_option("--from", opts->from,
                  "first posture: seconds of the stream's clock (90.5), or UTC (2026-12-02T08:00:00Z; --db only)");
  cmd->add_option("--to", opts->to, "postures before this");
  cmd->add_option("--out", opts->out, "directory for spine.mot and spine.trc")->required();
  cmd->callback([opts, &exit_code] {
    using namespace exporting;
    if (opts->db.empty() == opts->postures.empty())
      return exit_code.fail(Error{"give one of --db FILE or --postures FILE"}, 2);
    TimeRange range;
    for (auto [text, bound, name] : {std::tuple{&opts->from, &range.from, "--from"}, std::tuple{&opts->to, &range.to, "--to"}}) {
      if (text->empty()) continue;
      auto t = report::parse_time_point(*text);  // the same syntax as spinewatch report
      if (!t) return exit_code.fail(Error{std::string(name) + " " + t.error().message}, 2);
      *bound = TimeRange::Bound{t->utc, t->ns};
    }
    std::vector<SourceLine> lines;
    std::string source;
    if (!opts->db.empty()) {
      source = "database " + opts->db;
      auto stored = read_stored_posture_lines(opts->db);
      if (!stored) return exit_code.fail(stored.error());
      lines.reserve(stored->size());
      for (std::size_t i = 0; i < stored->size(); ++i)
        lines.push_back({std::move((*stored)[i].line), fmt::format("{}: posture row {}", opts->db, i + 1),
                         (*stored)[i].stored_ns});
    } else {
      source = opts->postures;
      auto read = read_ndjson_lines(opts->postures);
      if (!read) return exit_code.fail(read.error());
      lines = std::move(read).value();
    }
    auto rows = select_rows(lines, range);
    if (!rows) return exit_code.fail(rows.error());
    if (rows->rows.empty())
      return exit_code.fail(Error{fmt::format("{}: no tracked posture in the range ({} postures, none tracking)",
                                              source, rows->postures)});
    std::error_code ec;
    std::filesystem::create_directories(opts->out, ec);
    if (ec) return exit_code.fail(Error{opts->out + ": cannot be created: " + ec.message()});
    const std::filesystem::path dir(opts->out);
    if (auto s = write_output((dir / "spine.mot").string(), mot_text(rows->rows, "spinewatch spine")); !s)
      return exit_code.fail(s.error());
    if (auto s = write_output((dir / "spine.trc").string(), trc_text(rows->rows, "spine.trc")); !s)
      return exit_code.fail(s.error());
    spdlog::info("export: {} rows at {:.2f} per second from {} ({} init or lost postures omitted) → {}/spine.mot, "
                 "{}/spine.trc",
                 rows->rows.size(), row_rate_hz(rows->rows), source, rows->omitted, opts->out, opts->out);
  });
}

}  // namespace spinewatch::cli

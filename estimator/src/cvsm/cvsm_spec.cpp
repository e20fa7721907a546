// config/cvsm-generic.toml → CvsmSpec, with "FILE:LINE: field: problem" errors.
#include <fmt/format.h>
#include <toml++/toml.h>

#include "common/toml_fields.hpp"

#include "spinewatch/estimator/cvsm/body_model.hpp"

namespace spinewatch {
std::string_view generic_cvsm_toml();  // embedded at build time

Result<CvsmSpec> parse_cvsm_spec(std::string_view text, std::string_view source) {
  auto parsed = detail::parse_toml(text, source);
  if (!parsed) return parsed.error();
  const toml::table& root = *parsed;
  CvsmSpec spec;
  if (const toml::table* model = root["model"].as_table()) {
    auto cp = detail::toml_number(*model, "control_points", source, "model", kControlPoints, kControlPoints);
    if (!cp) return cp.error();
  }
  const toml::array* trunk = root["trunk"].as_array();
  if (!trunk || trunk->size() != kVertebraCount)
    return Error{fmt::format("{}: [[trunk]]: expected {} entries T1…L5", source, kVertebraCount)};
  for (std::size_t i = 0; i < kVertebraCount; ++i) {
    const toml::table* t = (*trunk)[i].as_table();
    const std::string ctx = fmt::format("trunk[{}]", i);
    if (!t) return Error{fmt::format("{}: {}: expected a table", source, ctx)};
    auto level = (*t)["level"].value<std::string>();
    if (!level || *level != kVertebraNames[i])
      return Error{fmt::format("{}: {}.level: expected \"{}\"", detail::toml_where(source, *t), ctx, kVertebraNames[i])};
    CvsmSpec::Trunk& out = spec.trunk[i];
    for (auto [key, field, min, max] : {std::tuple{"half_width", &out.half_width, 0.01, 0.3},
                                        std::tuple{"depth", &out.depth, 0.01, 0.3},
                                        std::tuple{"spine_fraction", &out.spine_fraction, 0.05, 0.95}}) {
      auto v = detail::toml_number(*t, key, source, ctx, min, max);
      if (!v) return v.error();
      *field = *v;
    }
  }
  const toml::array* parts = root["part"].as_array();
  if (!parts) return Error{fmt::format("{}: [[part]]: missing", source)};
  for (std::size_t i = 0; i < parts->size(); ++i) {
    const toml::table* p = (*parts)[i].as_table();
    const std::string ctx = fmt::format("part[{}]", i);
    if (!p) return Error{fmt::format("{}: {}: expected a table", source, ctx)};
    CvsmSpec::Part out;
    auto chain = (*p)["chain"].value<std::string>();
    if (!chain || (*chain != "pelvis" && *chain != "shoulder" && *chain != "head" && *chain != "arm" && *chain != "leg"))
      return Error{fmt::format("{}: {}.chain: expected pelvis, shoulder, head, arm or leg", detail::toml_where(source, *p), ctx)};
    auto attach = (*p)["attach"].value<std::string>();
    if (!attach || (*attach != "hip" && !vertebra_index(*attach)))
      return Error{fmt::format("{}: {}.attach: expected a vertebra T1…L5 or \"hip\"", detail::toml_where(source, *p), ctx)};
    if ((*chain == "leg") != (*attach == "hip"))
      return Error{fmt::format("{}: {}.attach: legs, and only legs, attach to \"hip\"", detail::toml_where(source, *p), ctx)};
    out.chain = *chain;
    out.attach = *attach;
    for (auto [key, field, min, max] : {std::tuple{"y", &out.y, 0.0, 1.1}, std::tuple{"x", &out.x, -0.3, 0.3},
                                        std::tuple{"z", &out.z, -0.3, 0.3}, std::tuple{"half_width", &out.half_width, 0.001, 0.3},
                                        std::tuple{"front", &out.front, 0.001, 0.3}, std::tuple{"back", &out.back, 0.001, 0.3}}) {
      auto v = detail::toml_number(*p, key, source, ctx, min, max);
      if (!v) return v.error();
      *field = *v;
    }
    spec.parts.push_back(std::move(out));
  }
  const toml::table* hip = root["hip"].as_table();
  if (!hip) return Error{fmt::format("{}: [hip]: missing", source)};
  for (auto [key, field, min, max] : {std::tuple{"y", &spec.hip_y, 0.3, 0.7}, std::tuple{"x", &spec.hip_x, -0.2, 0.2},
                                      std::tuple{"z", &spec.hip_z, 0.0, 0.2}, std::tuple{"thigh", &spec.thigh, 0.1, 0.4}}) {
    auto v = detail::toml_number(*hip, key, source, "hip", min, max);
    if (!v) return v.error();
    *field = *v;
  }
  return spec;
}

const CvsmSpec& generic_cvsm_spec() {
  static const CvsmSpec spec = [] {
    auto parsed = parse_cvsm_spec(generic_cvsm_toml(), "config/cvsm-generic.toml");
    // The embedded file is tested; a failure here is a build defect.
    if (!parsed) throw std::runtime_error(parsed.error().message);
    return std::move(parsed).value();
  }();
  return spec;
}

}  // namespace spinewatch

#pragma once
// The worker in view, as far as the station is told: stature and mass when
// someone entered them (config [subject], the `set_worker` command of
// docs/protocol.md), otherwise what the estimator measures or estimates.
// The posture stream says which (the "worker" field).
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

namespace spinewatch {

struct KnownWorker {
  std::optional<double> stature_mm;  // barefoot, as an anthropometer measures it
  std::optional<double> mass_kg;
  // Skin landmarks of the spine, standing barefoot, measured once at the
  // station's set-up with a tape or an anthropometer, as ANSUR II's
  // measurers took them: the C7 spinous process tip (`cervicaleheight`)
  // and the top of the iliac crest on the side (`iliocristaleheight`).
  // No outline shows them: from the silhouettes alone they are predicted
  // within 11 mm (C7) and 23 mm (crest) SD, and that spread is most of
  // the station's error on measured people (docs/anthropometry.md, "What
  // the outline cannot tell"). Given, they place T1 and L5 directly.
  // (Initialised so that {stature, mass} still spells a worker without them.)
  std::optional<double> c7_height_mm = std::nullopt;
  std::optional<double> iliac_crest_height_mm = std::nullopt;
  bool operator==(const KnownWorker&) const = default;
};

// A known worker's values taken together: the landmarks below the stature,
// the crest below C7 by at least a trunk, each within what adults measure.
// An error names the field and why.
struct WorkerCheck {
  bool ok = true;
  std::string message;
};
WorkerCheck check_known_worker(const KnownWorker& worker);

// Where a body value in the stream comes from.
enum class BodyValueSource : std::uint8_t {
  Given,      // entered for this worker
  Measured,   // from the silhouettes (the stature standing: the top of the head)
  Estimated,  // inferred (the stature seated, the mass from the stature)
};
std::string_view to_string(BodyValueSource source);

struct WorkerBody {
  double stature_mm = 0;
  BodyValueSource stature_source = BodyValueSource::Estimated;
  double mass_kg = 0;
  BodyValueSource mass_source = BodyValueSource::Estimated;
  // A given stature the silhouettes contradict (standing, the top of the
  // head more than kStatureMismatchMm above it): not used; the stature is
  // then the measured one. Most likely the wrong worker was set. (A body
  // shorter than given may be bending: that is not a contradiction.)
  std::optional<double> rejected_stature_mm;
  // The given skin landmarks that placed the spine (absent: the spine was
  // placed from the stature by the regressions). Set aside with a
  // rejected stature: they were measured on the same, other, person.
  std::optional<double> c7_height_mm = std::nullopt;
  std::optional<double> iliac_crest_height_mm = std::nullopt;
};

// How far the standing top of the head may rise above a given stature
// before the stature is taken for someone else's: shoes and hair (up to about 40 mm) and the
// measurement (8.4 mm worst on 40 ANSUR test subjects) stay well inside it;
// a spine placed for a body 80 mm taller or shorter is off by about 74 mm
// at T1 and 49 mm at L5 (the stature-only regressions' slopes, 0.93 and
// 0.62, config/anthropometry.toml): more than the station may publish as
// tracking without a word.
inline constexpr double kStatureMismatchMm = 80;

// The body-mass index the mass is estimated with when it is not given: the
// median of the ANSUR II training subjects (both sexes; 26.66 kg/m²). On
// the disjoint test subjects the mass so estimated is off by 12.0 kg SD
// (p95 23 kg): loads from an estimated mass are as uncertain, which is why
// the stream says so. tests/tools/anthropometry recompute it from the data.
inline constexpr double kMedianBmi = 26.66;
double estimated_mass_kg(double stature_mm);

}  // namespace spinewatch

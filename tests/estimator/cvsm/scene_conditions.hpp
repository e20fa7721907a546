#pragma once
// The scene conditions the background lifecycle is tested on (issue 15,
// docs/phantom.md "Conditions"): how the recording is rendered and what
// the estimator is given. `clean` is the reference every other condition
// is compared with: the same motion, the empty scene stored.
#include <array>
#include <span>
#include <string>
#include <string_view>

#include "test_support.hpp"
#include "phantom_run.hpp"
#include "scene_run.hpp"
#include "spinewatch/phantom/phantom.hpp"

namespace spinewatch::test {

struct SceneCondition {
  std::string_view name;
  bool stored_background = true;  // the estimator gets the empty scene
  int empty_frames = 0;           // 0: the subject is in view from the first frame
  double light_drift = 0;
  bool passer_by = false;
  bool shadow = false;
  bool colour = false;      // YUYV with chroma, the stored background in colour
  bool camouflage = false;  // clothing as bright as the wall
};

inline constexpr std::array<SceneCondition, 9> kSceneConditions = {{
    {"clean", true, 0, 0, false, false},
    {"learnt", false, 10, 0, false, false},      // empty frames first, background learnt from them
    {"bootstrap", false, 0, 0, false, false},    // subject in view, no background at all
    {"light_drift", true, 0, 0.35, false, false},
    {"passer_by", true, 0, 0, true, false},
    {"shadow", true, 0, 0, false, true},         // grey: a shadow cannot be told from clothing
    {"colour", true, 0, 0, false, false, true},  // the colour reference
    {"colour_shadow", true, 0, 0, false, true, true},
    {"camouflage", true, 0, 0, false, false, true, true},
}};

inline std::span<const SceneCondition> scene_conditions() { return kSceneConditions; }
inline const SceneCondition* find_scene_condition(std::string_view name) {
  for (const auto& c : kSceneConditions)
    if (c.name == name) return &c;
  return nullptr;
}

// Long enough for the subject model (10 frames) and a whole movement after
// it, and for the passer-by to cross (they enter a third of the way in).
inline int scene_frames(std::string_view scenario) { return scenario == "fast" ? 60 : 120; }

inline Result<phantom::PhantomSequence> scene_sequence(const std::string& scenario, const std::string& subject_name,
                                                       unsigned seed, const SceneCondition& c) {
  auto subject = phantom::load_subject(test::source_dir() + "/config/subjects/" + subject_name + ".json");
  if (!subject.ok()) return subject.error();
  phantom::PhantomOptions po;
  po.scenario = scenario;
  po.subject = *subject;
  po.frames = scene_frames(scenario);
  po.seed = seed;
  po.empty_frames = c.empty_frames;
  po.light_drift = c.light_drift;
  po.passer_by = c.passer_by;
  po.shadow = c.shadow;
  po.colour = c.colour;
  po.camouflage = c.camouflage;
  return phantom::PhantomSequence::create(po);
}

inline SceneRunOptions scene_run_options(const SceneCondition& c) {
  SceneRunOptions o;
  o.stored_background = c.stored_background;
  return o;
}

}  // namespace spinewatch::test

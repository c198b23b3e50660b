#include "observation_setup.hpp"

#include <cstdio>
#include <memory>

#ifdef LIESERVO_DEMO_WITH_REAL_OBSERVATIONS
#include "lieservo_sim/real_observation.hpp"
#endif

namespace lieservo::sim::programs {

void addObservationOptions(CLI::App& app, ObservationChoice& choice, bool with_calibration) {
  app.add_option("--observations", choice.mode,
                 "'real': the card's GDN on the nearest labelled TacTip image it did not train on; 'gaussian': "
                 "the calibrated Gaussian model; 'auto': real when the data set is there")
      ->capture_default_str()
      ->check(CLI::IsMember({"auto", "real", "gaussian"}));
  app.add_option("--data", choice.data_dir, "the TacTip data set for 'real'")->capture_default_str();
  if (with_calibration)
    app.add_option("--calibration", choice.calibration,
                   "the Gaussian model's error calibration: the model card's measured MAE (falls back to the "
                   "paper's) or the paper's Table 1")
        ->capture_default_str()
        ->check(CLI::IsMember({"card", "paper"}));
  // Noted while parsing (the App, and its options, do not outlive the parse).
  app.add_option("--model-card", choice.model_card,
                 "the GDN's model card: its measured MAE calibrates the Gaussian model, its network runs the "
                 "'real' mode")
      ->capture_default_str()
      ->each([&choice](const std::string&) { choice.card_given = true; });
}

int setUpObservations(const ObservationChoice& choice, TaskOptions& opt, std::string& note) {
  const bool card_given = choice.card_given;
  if (choice.calibration == "card" && !GdnCalibration::fromModelCard(choice.model_card, opt.calibration)) {
    if (card_given) {
      std::fprintf(stderr, "--model-card %s: cannot read models.gdn's measured MAE from it\n",
                   choice.model_card.c_str());
      return cli::kUsageOrSetup;
    }
    std::printf("note: no readable GDN model card at %s, using the paper's Table 1\n", choice.model_card.c_str());
  }
  note.clear();
#ifdef LIESERVO_DEMO_WITH_REAL_OBSERVATIONS
  // 'auto' falls back to the Gaussian model only when the data set is absent; with the data set
  // there, anything that stops the real mode (a corrupted model or params file) is a set-up error.
  RealObservationOptions ro;
  ro.data_dir = choice.data_dir;
  ro.model_card = choice.model_card;
  if (choice.mode == "real" || (choice.mode == "auto" && ro.dataSetPresent())) {
    try {
      opt.observations = std::make_shared<RealGdnObservations>(ro);
    } catch (const SceneError& e) {
      std::fprintf(stderr, "set-up error: %s\n", e.what());
      return cli::kUsageOrSetup;
    }
  } else if (choice.mode == "auto") {
    note = "(no TacTip data set at " + choice.data_dir + ": the `real` mode needs it)";
  }
#else
  if (choice.mode == "real") {
    std::fprintf(stderr, "--observations real: this build has no `real` mode (it needs OpenCV and nanoflann)\n");
    return cli::kUsageOrSetup;
  }
  if (choice.mode == "auto") note = "(this build has no `real` mode: it needs OpenCV and nanoflann)";
#endif
  return -1;
}

bool observationsFailed(const TaskOptions& opt) {
#ifdef LIESERVO_DEMO_WITH_REAL_OBSERVATIONS
  if (const auto* real = dynamic_cast<const RealGdnObservations*>(opt.observations.get());
      real && !real->lastError().empty()) {
    std::fprintf(stderr, "\nset-up error: real observations: %s\n", real->lastError().c_str());
    return true;
  }
#else
  (void)opt;
#endif
  return false;
}

std::string observationsRan(const TaskOptions& opt, const std::string& note) {
#ifdef LIESERVO_DEMO_WITH_REAL_OBSERVATIONS
  if (const auto* real = dynamic_cast<const RealGdnObservations*>(opt.observations.get()))
    return "real mode, " + std::to_string(real->evaluatedImages()) + " distinct TacTip images run through the GDN";
#else
  (void)opt;
#endif
  return "gaussian mode" + (note.empty() ? std::string() : " " + note);
}

}  // namespace lieservo::sim::programs

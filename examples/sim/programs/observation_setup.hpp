// observation_setup.hpp — the simulation programs' observation options (lieservo_demo,
// lieservo_push_start_map): which observations the tasks see and how they are set up.
//
//   --observations auto|real|gaussian   'real': the card's GDN on the nearest labelled TacTip
//                                       image it did not train on; 'gaussian': the calibrated
//                                       Gaussian model; 'auto': real when the data set is there
//   --data DIR                          the TacTip data set for 'real'
//   --model-card FILE                   the GDN's model card: the Gaussian model's calibration
//                                       (its measured MAE) and the network of 'real'
//   --calibration card|paper            (the demo) the card's MAE, or the paper's Table 1
#pragma once

#include <string>

#include <lieservo_cli/cli.hpp>

#include "lieservo_sim/tasks.hpp"

namespace lieservo::sim::programs {

struct ObservationChoice {
  std::string mode = "auto";
  std::string data_dir = LIESERVO_DEFAULT_DATA_DIR;
  std::string model_card = LIESERVO_SIM_MODEL_CARD;
  std::string calibration = "card";
  bool card_given = false;  ///< --model-card was on the command line (set while parsing)
};

/// Adds the options above to `app`; `with_calibration` adds --calibration.
void addObservationOptions(CLI::App& app, ObservationChoice& choice, bool with_calibration);

/// Sets up opt.calibration and opt.observations as chosen. Returns -1 to go on, or the exit
/// status (kUsageOrSetup, with the message on stderr naming the option or file). A model card
/// that cannot be read falls back to the paper's Table 1 with a note, unless --model-card
/// named it. `note` says why 'auto' chose the Gaussian model ("" when it did not).
int setUpObservations(const ObservationChoice& choice, TaskOptions& opt, std::string& note);

/// After a task: true (with the message on stderr) when a real-mode observation could not be
/// made (an unreadable or truncated image, a network that fails): a set-up error, exit 2.
bool observationsFailed(const TaskOptions& opt);

/// The line after the runs: which mode ran, and how many images the real mode used.
std::string observationsRan(const TaskOptions& opt, const std::string& note);

}  // namespace lieservo::sim::programs

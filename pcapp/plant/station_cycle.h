// The station mode: the station cycle of shared/plant (one controller step
// and one plant step per cycle, docs/plant.md "The cycle") on the registers
// the app read; the RUN command goes back to the gateway. This file adds what
// the app shows of it: events, the status line, log columns, the summary.
#pragma once
#include "cycle_mode.h"
#include "plant/station_cycle.h"

namespace mb2co {
namespace pcapp {

class StationCycle : public CycleMode {
 public:
  /// `config` must have passed check_plant_config().
  StationCycle(const RegisterLayout& layout, const plant::PlantConfig& config);

  std::vector<Field> required_reads() const override;
  std::vector<Field> optional_reads() const override;
  std::vector<Field> writes() const override { return {Field::kRunCommand}; }

  void step(const RegisterImage& in, RegisterImage& out) override;
  void step_offline() override;
  void link_lost() override;
  void safe_outputs(RegisterImage& out) const override;

  std::string take_event() override;
  std::string status() const override;
  std::vector<const char*> column_names() const override;
  void columns(std::vector<LogValue>& out) const override;
  std::string summary() const override;

  const plant::Controller& controller() const { return cycle_.controller(); }
  const plant::Plant& plant() const { return cycle_.plant(); }
  const Panel& panel() const { return cycle_.panel(); }

 private:
  void note_changes(const plant::ControllerCounters& before, plant::State state_before);

  const RegisterLayout& layout_;
  plant::StationCycle cycle_;
  std::string event_;
};

const char* state_name(plant::State state);
const char* stop_cause_name(plant::StopCause cause);

}  // namespace pcapp
}  // namespace mb2co

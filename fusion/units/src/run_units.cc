// The registry's units run stage by stage (unit.h).

#include <algorithm>
#include <future>

#include "wearscar/fusion/unit.h"

namespace wearscar::fusion {

struct UnitRunner::Running {
  const AnalysisUnit* unit;
  std::shared_ptr<const FuseOptions> options;
  std::shared_future<std::shared_ptr<const void>> result;
};

UnitRunner::UnitRunner(const force::ForceRecord& record, bool parallel)
    : record_(record), parallel_(parallel) {}

UnitRunner::~UnitRunner() {
  for (const auto& r : running_) {
    if (r->result.valid()) r->result.wait();
  }
}

void UnitRunner::Start(UnitStage stage,
                       const ForceAnalysis& force,
                       const FuseOptions& options,
                       const TestResult* judged) {
  auto copied = std::make_shared<const FuseOptions>(options);
  for (const AnalysisUnit* unit : AnalysisUnits()) {
    if (unit->Stage(record_) != stage || !unit->Wanted(options)) continue;
    // What it reads: the results collected, and the units still running
    // that it names (each waited for inside its task).
    std::vector<std::shared_ptr<Running>> reads;
    for (const std::string& kind : unit->Spec().reads) {
      for (const auto& r : running_) {
        if (kind == r->unit->Kind()) reads.push_back(r);
      }
    }
    auto running = std::make_shared<Running>();
    running->unit = unit;
    running->options = copied;
    const bool own_thread = parallel_ && unit->WorthAThread();
    running->result = std::async(
        own_thread ? std::launch::async : std::launch::deferred,
        [this, unit, reads, &force, copied, judged, seen = done_]() mutable {
          for (const auto& r : reads) r->unit->Store(r->result.get(), &seen);
          const UnitInput in{record_, force, *copied, judged, seen};
          return unit->RunErased(in);
        });
    running_.push_back(std::move(running));
  }
}

void UnitRunner::Collect(UnitResults* units) {
  // Every unit waited for before any error is passed on: none still runs
  // on what the caller is about to free.
  for (const auto& r : running_) r->result.wait();
  for (const auto& r : running_) {
    r->unit->Store(r->result.get(), units);
    r->unit->Store(r->result.get(), &done_);
  }
  running_.clear();
}

bool UnitRunner::CollectOne(std::string_view kind, UnitResults* units) {
  const auto it =
      std::find_if(running_.begin(), running_.end(), [&](const auto& r) {
        return kind == r->unit->Kind();
      });
  if (it == running_.end()) return false;
  const std::shared_ptr<Running> r = *it;
  r->result.wait();
  running_.erase(it);
  r->unit->Store(r->result.get(), units);
  r->unit->Store(r->result.get(), &done_);
  return true;
}

std::shared_ptr<const void> UnitRunner::AwaitErased(
    std::string_view kind) const {
  for (const auto& r : running_) {
    if (kind == r->unit->Kind()) return r->result.get();
  }
  return nullptr;
}

std::vector<std::pair<const AnalysisUnit*, const void*>> UnitsThatRan(
    const TestResult& r) {
  std::vector<std::pair<const AnalysisUnit*, const void*>> ran;
  for (const AnalysisUnit* unit : AnalysisUnits()) {
    if (const void* result = r.units.Of(unit->Kind()))
      ran.emplace_back(unit, result);
  }
  return ran;
}

void SayWhatTheUnitsFound(TestResult* r) {
  for (const auto& [unit, result] : UnitsThatRan(*r))
    unit->SayErased(result, r);
}

}  // namespace wearscar::fusion

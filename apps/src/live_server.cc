#include "live_server.h"

#include <fmt/format.h>
#include <httplib.h>

#include <cmath>

#include "live_page.h"
#include "usage_error.h"

namespace wearscar::app {
namespace {

// Numbers for the page: NaN as null.
nlohmann::json Number(double v, double scale = 1e6) {
  if (!std::isfinite(v)) return nullptr;
  return std::round(v * scale) / scale;
}

}  // namespace

LiveServer::LiveServer(int port)
    : server_(std::make_unique<httplib::Server>()) {
  server_->Get("/", [](const httplib::Request&, httplib::Response& res) {
    res.set_content(kLivePage, "text/html; charset=utf-8");
  });
  server_->Get("/state.json",
               [this](const httplib::Request& req, httplib::Response& res) {
                 int since = 0;
                 if (req.has_param("since")) {
                   try {
                     since =
                         std::max(0, std::stoi(req.get_param_value("since")));
                   } catch (const std::exception&) {
                     since = 0;
                   }
                 }
                 res.set_header("Cache-Control", "no-store");
                 res.set_content(State(since).dump(), "application/json");
               });
  port_ = port == 0 ? server_->bind_to_any_port("127.0.0.1")
                    : (server_->bind_to_port("127.0.0.1", port) ? port : -1);
  if (port_ <= 0) {
    throw UsageError(fmt::format(
        "watch: --port {}: cannot listen on 127.0.0.1 (in use?); expected a "
        "free port, or 0 for any",
        port));
  }
  thread_ = std::thread([this] { server_->listen_after_bind(); });
}

LiveServer::~LiveServer() {
  server_->stop();
  if (thread_.joinable()) thread_.join();
}

std::string LiveServer::Address() const {
  return fmt::format("http://127.0.0.1:{}/", port_);
}

void LiveServer::Update(const fusion::LiveAnalysis& live) {
  std::lock_guard<std::mutex> lock(mutex_);
  const auto& all = live.cycles();
  if (all.size() < cycles_.size()) {
    cycles_.clear();  // a new test
    ++restarts_;
  }
  if (all.size() == cycles_.size()) return;
  cycles_.insert(cycles_.end(), all.begin() + cycles_.size(), all.end());
  loop_ = live.loop();
  map_ = live.map();
  verdict_ = live.verdict();
  steady_ = live.steady();
}

void LiveServer::Event(const fusion::LiveEvent& e) {
  std::lock_guard<std::mutex> lock(mutex_);
  events_.push_back(e);
}

nlohmann::json LiveServer::State(int since) const {
  std::lock_guard<std::mutex> lock(mutex_);
  nlohmann::json s;
  s["restarts"] = restarts_;
  s["total"] = cycles_.size();
  s["verdict"] = verdict_;
  s["steady"] = steady_;
  nlohmann::json rows = nlohmann::json::array();
  for (size_t i = std::min<size_t>(since, cycles_.size()); i < cycles_.size();
       ++i) {
    const fusion::LiveCycle& c = cycles_[i];
    rows.push_back({c.cycle,
                    Number(c.mu_hat),
                    Number(c.mu_low),
                    Number(c.mu_high),
                    Number(c.mu_mean),
                    Number(c.cost, 1e4),
                    Number(c.cost_excess, 1e4),
                    Number(c.depth_mm),
                    c.running_in});
  }
  s["cycles"] = std::move(rows);
  nlohmann::json events = nlohmann::json::array();
  for (const auto& e : events_)
    events.push_back({{"kind", e.kind},
                      {"cycle", e.cycle},
                      {"message", e.message},
                      {"good", e.good}});
  s["events"] = std::move(events);
  nlohmann::json loop = {{"cycle", loop_.cycle}};
  nlohmann::json x = nlohmann::json::array(), q = nlohmann::json::array(),
                 m = nlohmann::json::array();
  // At most about 2000 points of the loop.
  const size_t step = std::max<size_t>(1, loop_.x_mm.size() / 2000);
  for (size_t i = 0; i < loop_.x_mm.size(); i += step) {
    x.push_back(Number(loop_.x_mm[i], 1e4));
    q.push_back(Number(loop_.q_n[i], 1e4));
    m.push_back(Number(loop_.q_model_n[i], 1e4));
  }
  loop["x"] = std::move(x);
  loop["q"] = std::move(q);
  loop["model"] = std::move(m);
  s["loop"] = std::move(loop);
  nlohmann::json map = {
      {"x", map_.x_mm}, {"first", map_.first_cycle}, {"last", map_.last_cycle}};
  nlohmann::json rows_map = nlohmann::json::array();
  for (const auto& r : map_.rows) {
    nlohmann::json row = nlohmann::json::array();
    for (double v : r) row.push_back(Number(v, 1e4));
    rows_map.push_back(std::move(row));
  }
  map["rows"] = std::move(rows_map);
  nlohmann::json track = nlohmann::json::array();
  for (const auto& r : map_.track_rows) {
    nlohmann::json row = nlohmann::json::array();
    for (double v : r) row.push_back(Number(v, 1e5));
    track.push_back(std::move(row));
  }
  map["track"] = std::move(track);
  s["map"] = std::move(map);
  return s;
}

}  // namespace wearscar::app

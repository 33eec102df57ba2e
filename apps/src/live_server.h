#pragma once
// The live page of `wearscar watch`: served on 127.0.0.1 while the test
// runs; the page asks for what is new every half second (no reload).

#include <memory>
#include <mutex>
#include <nlohmann/json.hpp>
#include <string>
#include <thread>
#include <vector>

#include "wearscar/fusion/live.h"

namespace httplib {
class Server;
}

namespace wearscar::app {

class LiveServer {
 public:
  // Listens on 127.0.0.1:port (0: a free port); throws UsageError when it
  // cannot.
  explicit LiveServer(int port);
  ~LiveServer();
  LiveServer(const LiveServer&) = delete;
  LiveServer& operator=(const LiveServer&) = delete;
  std::string Address() const;
  // The analysis as it stands now (new cycles, the latest loop, the map).
  void Update(const fusion::LiveAnalysis& live);
  void Event(const fusion::LiveEvent& e);

 private:
  nlohmann::json State(int since) const;
  std::unique_ptr<httplib::Server> server_;
  std::thread thread_;
  int port_ = 0;
  mutable std::mutex mutex_;
  std::vector<fusion::LiveCycle> cycles_;
  std::vector<fusion::LiveEvent> events_;
  fusion::LiveLoop loop_;
  fusion::LiveMap map_;
  std::string verdict_;
  bool steady_ = false;
  int restarts_ = 0;
};

}  // namespace wearscar::app

// The viewer's simulation, on a thread of its own: the window never waits for a frame to be
// simulated (a 128 × 128 cloth can take a second per frame), so the camera, the panel and the
// mouse stay responsive. The window reads published snapshots and sends commands; the thread
// runs the commands between frames, in the order they were sent.
#pragma once

#include <condition_variable>
#include <cstdint>
#include <deque>
#include <functional>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "drape/simulation.h"
#include "render/picking.h"

namespace drape::app {

/// What the window shows of the simulation: a copy taken after a frame or a command.
struct SimSnapshot {
  std::shared_ptr<const ClothModel> model;  ///< shared until the cloth is rebuilt
  ClothState state;
  std::vector<Collider> colliders;
  std::vector<Vec3> collider_offsets;  ///< m, where the hand has carried each (Simulation)
  SceneDef def;                        ///< the settings in effect
  Diagnostics diagnostics;
  /// Crossing triangle pairs (count_self_intersections), counted every kCountEvery frames and
  /// after every command
  int64_t self_intersections = 0;
  int64_t frame = 0;
  double time = 0.0;     ///< s, simulated
  int substeps = 0;      ///< per frame
  double step_ms = 0.0;  ///< wall time of one frame's step, smoothed
  int32_t grabbed = -1;  ///< the held particle, −1: none
  bool diverged = false;
  int64_t diverged_frame = -1;
  std::string divergence;  ///< why, with a hint
  std::string error;       ///< the last command's failure (a setting refused), or empty
};

class SimThread {
 public:
  /// Starts the thread, paused. `realtime`: while playing, frames follow the wall clock (one
  /// frame per dt at most); otherwise frames are taken only through step_and_wait(). `threads`:
  /// the simulation's threads (0: chosen by the clock, ThreadChooser).
  SimThread(std::unique_ptr<Simulation> sim, bool realtime, int threads = 0);
  ~SimThread();  ///< finishes the frame under way, then stops
  SimThread(const SimThread&) = delete;
  SimThread& operator=(const SimThread&) = delete;

  /// The latest snapshot; never null.
  std::shared_ptr<const SimSnapshot> snapshot() const;

  void set_playing(bool playing);
  /// Pause, then one more frame.
  void request_step();
  /// Runs the pending commands and one frame, and returns once its snapshot is published.
  void step_and_wait();
  /// Returns once every command sent so far has run and its snapshot is published.
  void sync();

  // Commands.
  void replace(std::unique_ptr<Simulation> sim);    ///< a new cloth
  void reconfigure(const SceneDef& def);            ///< live settings; a new cloth when needed
  void grab(int32_t particle, const Vec3& target);  ///< hold `particle` at `target`
  void move_grab(const Vec3& target);
  void release(bool with_hand_velocity);  ///< let go (at rest, or flicked)
  void toggle_pin(int32_t particle);
  void move_collider(int k, const Vec3& offset);  ///< carry collider k `offset` from its place

 private:
  void post(std::function<void()> command);
  void loop(int threads);
  void publish(double step_ms);

  std::unique_ptr<Simulation> sim_;  // touched by the thread only, after construction
  render::HandTracker hand_;
  const bool realtime_;
  std::string error_;
  double step_ms_ = 0.0;
  // The self-intersection count, taken every this many frames while playing: one count costs
  // about a frame's step of a large cloth.
  static constexpr int64_t kCountEvery = 10;
  int64_t self_intersections_ = 0;
  int64_t counted_frame_ = -1;  ///< the frame self_intersections_ was counted at

  mutable std::mutex mutex_;      // guards everything below
  std::condition_variable wake_;  // the thread: work arrived
  std::condition_variable done_;  // the window: work finished
  std::deque<std::function<void()>> commands_;
  bool playing_ = false;
  bool stop_ = false;
  int64_t steps_requested_ = 0;         // frames asked for by request_step() / step_and_wait()
  uint64_t posted_ = 0, finished_ = 0;  // work items sent and completed
  std::shared_ptr<const SimSnapshot> snapshot_;
  std::shared_ptr<const ClothModel> model_;

  std::thread thread_;  // last: starts once everything above exists
};

}  // namespace drape::app

// The viewer's simulation thread: commands run in the order sent, between frames; snapshots
// show their effect; real-time play follows the wall clock; a refused setting is reported.
#include <gtest/gtest.h>

#include <chrono>
#include <memory>
#include <thread>

#include "app/sim_thread.h"

namespace drape::app {
namespace {

SceneDef small_scene() {
  SceneDef def;  // the documented defaults: the hang scene
  def.cloth.cols = def.cloth.rows = 8;
  def.solver.method = Method::symplectic;  // whose automatic substeps the tests set and refuse
  return def;
}

TEST(SimThread, StepAndWaitAdvancesOneFrameAndPublishesIt) {
  SimThread t(std::make_unique<Simulation>(small_scene()), false);
  EXPECT_EQ(t.snapshot()->frame, 0);
  t.step_and_wait();
  t.step_and_wait();
  const auto s = t.snapshot();
  EXPECT_EQ(s->frame, 2);
  EXPECT_EQ(s->model->size(), 64);
  EXPECT_GT(s->step_ms, 0.0);
  // Free particles fell; the snapshot is the simulation's state, not the start.
  EXPECT_LT(s->state.x[63].y(), s->model->rest_position[63].y());
}

TEST(SimThread, CommandsRunInOrderBeforeTheNextFrame) {
  SimThread t(std::make_unique<Simulation>(small_scene()), false);
  const Vec3 a(0.5, 1.0, 0.3), b(0.7, 1.2, 0.4);
  t.grab(60, a);
  t.move_grab(b);
  t.step_and_wait();
  auto s = t.snapshot();
  EXPECT_EQ(s->grabbed, 60);
  EXPECT_EQ(s->state.x[60], b);  // held where the last move put it, through the frame
  t.release(false);
  t.toggle_pin(10);
  t.sync();
  s = t.snapshot();
  EXPECT_EQ(s->grabbed, -1);
  EXPECT_TRUE(s->state.pinned[10]);
}

TEST(SimThread, ReleaseWithTheHandsVelocityFlicksTheParticle) {
  SimThread t(std::make_unique<Simulation>(small_scene()), false);
  const double dt = small_scene().solver.dt;
  t.grab(60, Vec3(0.0, 1.0, 0.0));
  t.step_and_wait();
  t.move_grab(Vec3(0.0, 1.0, 0.1));  // 0.1 m in one frame
  t.step_and_wait();
  t.release(true);
  t.sync();
  EXPECT_NEAR(t.snapshot()->state.v[60].z(), 0.1 / dt, 1e-9);
}

TEST(SimThread, SettingsApplyLiveOrRebuildTheClothAndRefusalsAreReported) {
  SimThread t(std::make_unique<Simulation>(small_scene()), false);
  t.step_and_wait();
  SceneDef def = small_scene();
  def.cloth.mass = 2.0;  // live: the cloth keeps its frame count
  t.reconfigure(def);
  t.sync();
  EXPECT_EQ(t.snapshot()->frame, 1);
  EXPECT_EQ(t.snapshot()->def.cloth.mass, 2.0);
  def.cloth.cols = 12;  // needs a new cloth
  t.reconfigure(def);
  t.sync();
  EXPECT_EQ(t.snapshot()->frame, 0);
  EXPECT_EQ(t.snapshot()->model->size(), 12 * 8);
  def.solver.substeps = 0;
  def.solver.max_substeps = 1;  // far too few for this stiffness: the solver refuses it
  t.reconfigure(def);
  t.sync();
  EXPECT_FALSE(t.snapshot()->error.empty());
  EXPECT_EQ(t.snapshot()->def.solver.max_substeps, small_scene().solver.max_substeps);
}

TEST(SimThread, RealTimePlayFollowsTheWallClockAndStopsOnPause) {
  SimThread t(std::make_unique<Simulation>(small_scene()), true);
  t.set_playing(true);
  std::this_thread::sleep_for(std::chrono::milliseconds(500));
  t.set_playing(false);
  t.sync();
  const int64_t frames = t.snapshot()->frame;
  // 0.5 s at 60 frames/s is 30 frames; a busy machine may run fewer, never many more.
  EXPECT_GT(frames, 3);
  EXPECT_LE(frames, 36);
  std::this_thread::sleep_for(std::chrono::milliseconds(100));
  EXPECT_LE(t.snapshot()->frame, frames + 1);  // paused (one frame may have been under way)
}

TEST(SimThread, DivergencePausesAndIsReported) {
  SceneDef def = small_scene();
  def.solver.substeps = 1;  // far above the stable step: the energy explodes
  SimThread t(std::make_unique<Simulation>(def), true);
  t.set_playing(true);
  for (int i = 0; i < 200 && !t.snapshot()->diverged; ++i)
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  const auto s = t.snapshot();
  ASSERT_TRUE(s->diverged);
  EXPECT_FALSE(s->divergence.empty());
  std::this_thread::sleep_for(std::chrono::milliseconds(50));
  EXPECT_EQ(t.snapshot()->frame, s->frame);
}

}  // namespace
}  // namespace drape::app

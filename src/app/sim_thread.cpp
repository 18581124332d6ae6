#include "app/sim_thread.h"

#include <algorithm>
#include <chrono>

#include "app/thread_chooser.h"
#include "drape/error.h"
#include "drape/self_intersections.h"

namespace drape::app {

namespace {
using Clock = std::chrono::steady_clock;
}

SimThread::SimThread(std::unique_ptr<Simulation> sim, bool realtime, int threads)
    : sim_(std::move(sim)), realtime_(realtime) {
  model_ = std::make_shared<ClothModel>(sim_->model());
  publish(-1.0);
  thread_ = std::thread([this, threads] { loop(threads); });
}

SimThread::~SimThread() {
  {
    std::lock_guard lock(mutex_);
    stop_ = true;
  }
  wake_.notify_all();
  thread_.join();
}

std::shared_ptr<const SimSnapshot> SimThread::snapshot() const {
  std::lock_guard lock(mutex_);
  return snapshot_;
}

void SimThread::set_playing(bool playing) {
  {
    std::lock_guard lock(mutex_);
    if (playing_ == playing) return;
    playing_ = playing;
  }
  wake_.notify_all();
}

void SimThread::post(std::function<void()> command) {
  {
    std::lock_guard lock(mutex_);
    commands_.push_back(std::move(command));
    ++posted_;
  }
  wake_.notify_all();
}

void SimThread::request_step() {
  {
    std::lock_guard lock(mutex_);
    playing_ = false;
  }
  post(nullptr);  // an empty command is a frame
}

void SimThread::step_and_wait() {
  post(nullptr);
  sync();
}

void SimThread::sync() {
  std::unique_lock lock(mutex_);
  const uint64_t ticket = posted_;
  done_.wait(lock, [&] { return finished_ >= ticket; });
}

void SimThread::replace(std::unique_ptr<Simulation> sim) {
  std::shared_ptr<Simulation> fresh(std::move(sim));
  post([this, fresh] {
    sim_ = std::make_unique<Simulation>(std::move(*fresh));
    model_ = std::make_shared<ClothModel>(sim_->model());
    hand_.start(Vec3::Zero());
  });
}

void SimThread::reconfigure(const SceneDef& def) {
  post([this, def] {
    // A diverged simulation steps no more: changed settings (a smaller dt, more substeps) start
    // the cloth afresh. The model is shared as it was: what changes live (stiffness, damping,
    // mass) is not drawn.
    if (sim_->diverged() || !sim_->reconfigure(def)) {
      sim_ = std::make_unique<Simulation>(def);
      model_ = std::make_shared<ClothModel>(sim_->model());
    }
  });
}

void SimThread::grab(int32_t particle, const Vec3& target) {
  post([this, particle, target] {
    sim_->grab(particle);
    hand_.start(target);
    sim_->move_grab(target);
  });
}

void SimThread::move_grab(const Vec3& target) {
  post([this, target] {
    hand_.move(target);
    sim_->move_grab(target);
  });
}

void SimThread::release(bool with_hand_velocity) {
  post([this, with_hand_velocity] {
    sim_->release(with_hand_velocity ? hand_.velocity() : Vec3::Zero());
  });
}

void SimThread::toggle_pin(int32_t particle) {
  post([this, particle] {
    if (particle < 0 || particle >= sim_->model().size()) return;
    sim_->set_pinned(particle, !sim_->state().pinned[particle]);
  });
}

void SimThread::move_collider(int k, const Vec3& offset) {
  post([this, k, offset] { sim_->move_collider(k, offset); });
}

void SimThread::loop(int threads) {
  // OpenMP's thread count belongs to the thread that opens the loops: this one.
  ThreadChooser chooser(threads);
  auto step = [this, &chooser] {
    chooser.before_frame();
    const auto t0 = Clock::now();
    sim_->step();
    const double ms = std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
    chooser.after_frame(ms);
    if (sim_->grabbed() >= 0) hand_.frame_done(sim_->def().solver.dt);
    return ms;
  };
  Clock::time_point due = Clock::now();
  std::unique_lock lock(mutex_);
  while (!stop_) {
    if (!commands_.empty()) {
      // Everything sent up to the next frame, then that frame; one snapshot for all of it.
      std::vector<std::function<void()>> batch;
      while (!commands_.empty()) {
        batch.push_back(std::move(commands_.front()));
        commands_.pop_front();
        if (!batch.back()) break;
      }
      lock.unlock();
      double ms = -1.0;
      for (const auto& command : batch) {
        if (!command) {
          ms = step();
          continue;
        }
        try {
          command();
          error_.clear();
        } catch (const InputError& e) {
          error_ = e.what();  // the simulation keeps its last good settings
        }
      }
      publish(ms);
      lock.lock();
      finished_ += batch.size();
      if (sim_->diverged()) playing_ = false;
      done_.notify_all();
      continue;
    }
    if (playing_ && realtime_ && !sim_->diverged()) {
      // Real time: a frame every dt of wall time; a simulation slower than that runs flat out,
      // and one that fell behind does not rush to catch up.
      const auto now = Clock::now();
      if (now < due) {
        wake_.wait_until(lock, due);
        continue;
      }
      const auto dt = std::chrono::duration_cast<Clock::duration>(
          std::chrono::duration<double>(sim_->def().solver.dt));
      due = std::max(due + dt, now - 4 * dt);
      lock.unlock();
      const double ms = step();
      publish(ms);
      lock.lock();
      if (sim_->diverged()) playing_ = false;
      continue;
    }
    wake_.wait(lock);
    due = Clock::now();
  }
}

void SimThread::publish(double step_ms) {
  auto s = std::make_shared<SimSnapshot>();
  if (step_ms >= 0.0) step_ms_ = step_ms_ == 0.0 ? step_ms : 0.9 * step_ms_ + 0.1 * step_ms;
  s->model = model_;
  s->state = sim_->state();
  s->colliders = sim_->colliders();
  for (int k = 0; k < static_cast<int>(s->colliders.size()); ++k)
    s->collider_offsets.push_back(sim_->collider_offset(k));
  s->def = sim_->def();
  s->diagnostics = sim_->diagnostics();
  if (step_ms < 0.0 || counted_frame_ < 0 || sim_->frame() - counted_frame_ >= kCountEvery) {
    self_intersections_ = count_self_intersections(sim_->model().triangles, sim_->state().x);
    counted_frame_ = sim_->frame();
  }
  s->self_intersections = self_intersections_;
  s->frame = sim_->frame();
  s->time = sim_->time();
  s->substeps = sim_->substeps_per_frame();
  s->step_ms = step_ms_;
  s->grabbed = sim_->grabbed();
  s->diverged = sim_->diverged();
  s->diverged_frame = sim_->diverged_frame();
  s->divergence = sim_->divergence();
  s->error = error_;
  std::lock_guard lock(mutex_);
  snapshot_ = std::move(s);
}

}  // namespace drape::app

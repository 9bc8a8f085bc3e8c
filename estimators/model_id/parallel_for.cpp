#include "estimators/model_id/parallel_for.hpp"

#include <algorithm>
#include <atomic>
#include <condition_variable>
#include <exception>
#include <memory>
#include <mutex>
#include <thread>
#include <vector>

namespace rnav {

namespace {

// The helper threads, kept until the process ends.
class Pool {
 public:
  ~Pool() {
    for (auto& w : workers_) {
      {
        std::lock_guard<std::mutex> lock(w->m);
        w->stop = true;
      }
      w->cv.notify_one();
      w->thread.join();
    }
  }

  struct Worker {
    std::mutex m;
    std::condition_variable cv;
    std::function<void()> task;  // the task to run (empty: none)
    bool stop = false;
    bool claimed = false;  // given a task, not yet released (under the pool's mutex)
    std::thread thread;
  };

  // Runs task on an idle helper, a new one when none is idle; the helper stays claimed until
  // release(). (A helper released while it still returns from the task takes its next task
  // once that is done: its task slot is empty from the moment it started the last one.)
  Worker* start(std::function<void()> task) {
    Worker* w = nullptr;
    {
      std::lock_guard<std::mutex> lock(m_);
      for (auto& x : workers_)
        if (!x->claimed) {
          w = x.get();
          break;
        }
      if (!w) {
        workers_.push_back(std::make_unique<Worker>());
        w = workers_.back().get();
        w->thread = std::thread([this, w] { run(*w); });
      }
      w->claimed = true;
    }
    {
      std::lock_guard<std::mutex> lock(w->m);
      w->task = std::move(task);
    }
    w->cv.notify_one();
    return w;
  }

  // The helpers of start() idle again (their tasks finished).
  void release(const std::vector<Worker*>& ws) {
    std::lock_guard<std::mutex> lock(m_);
    for (Worker* w : ws) w->claimed = false;
  }

 private:
  void run(Worker& w) {
    for (;;) {
      std::function<void()> task;
      {
        std::unique_lock<std::mutex> lock(w.m);
        w.cv.wait(lock, [&] { return w.task || w.stop; });
        if (!w.task) return;
        task = std::move(w.task);
        w.task = nullptr;
      }
      task();
    }
  }

  std::mutex m_;
  std::vector<std::unique_ptr<Worker>> workers_;
};

Pool& pool() {
  static Pool p;
  return p;
}

}  // namespace

void parallel_for(std::size_t n, int threads, const std::function<void(std::size_t)>& fn) {
  std::vector<std::exception_ptr> errors(n);
  std::atomic<std::size_t> next{0};
  auto work = [&] {
    for (std::size_t i; (i = next++) < n;) try {
        fn(i);
      } catch (...) {
        errors[i] = std::current_exception();
      }
  };
  const std::size_t helpers = std::min<std::size_t>(static_cast<std::size_t>(std::max(threads, 1)), n);
  std::mutex m;
  std::condition_variable done;
  std::size_t running = helpers > 0 ? helpers - 1 : 0;
  std::vector<Pool::Worker*> claimed;
  for (std::size_t t = 1; t < helpers; ++t)
    claimed.push_back(pool().start([&] {
      work();
      // notified under the lock: this call's frame (m, done) outlives the notification
      std::lock_guard<std::mutex> lock(m);
      if (--running == 0) done.notify_all();
    }));
  work();
  {
    std::unique_lock<std::mutex> lock(m);
    done.wait(lock, [&] { return running == 0; });
  }
  pool().release(claimed);
  for (const auto& e : errors)
    if (e) std::rethrow_exception(e);
}

}  // namespace rnav

// The one thread that owns the OpenGL context. An EGL/OpenGL context is current on one thread at a
// time, so every GL call of the process runs here: other threads post jobs and wait for them. Jobs
// run one at a time in submission order; an exception thrown by a job is rethrown in the caller.
#pragma once

#include <condition_variable>
#include <deque>
#include <functional>
#include <future>
#include <mutex>
#include <thread>

namespace culinarycut::render {

class RenderThread {
 public:
  // Starts the thread and runs `start` on it first (e.g. create the context); rethrows its
  // exception here, after the thread has stopped.
  explicit RenderThread(std::function<void()> start);
  // Runs `stop` on the thread after the queued jobs (e.g. free GL objects), then joins.
  ~RenderThread();
  RenderThread(const RenderThread&) = delete;
  RenderThread& operator=(const RenderThread&) = delete;

  // Runs `job` on the render thread and waits for it; safe to call from any thread.
  template <typename Result>
  Result Run(std::function<Result()> job) {
    std::packaged_task<Result()> task(std::move(job));
    std::future<Result> done = task.get_future();
    Post([&task] { task(); });
    return done.get();
  }

  void SetStop(std::function<void()> stop) { stop_ = std::move(stop); }
  std::thread::id id() const { return thread_.get_id(); }

 private:
  void Post(std::function<void()> job);
  void Loop(std::function<void()> start, std::promise<void>* started);

  std::mutex mutex_;
  std::condition_variable wake_;
  std::deque<std::function<void()>> jobs_;
  bool quit_ = false;
  std::function<void()> stop_;
  std::thread thread_;
};

}  // namespace culinarycut::render

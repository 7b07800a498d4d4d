#include "sim/render/render_thread.h"

namespace culinarycut::render {

RenderThread::RenderThread(std::function<void()> start) {
  std::promise<void> started;
  std::future<void> ready = started.get_future();
  thread_ = std::thread([this, start = std::move(start), &started]() mutable { Loop(std::move(start), &started); });
  try {
    ready.get();
  } catch (...) {
    thread_.join();  // the loop has already returned after a failed start
    throw;
  }
}

RenderThread::~RenderThread() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    quit_ = true;
  }
  wake_.notify_one();
  if (thread_.joinable()) thread_.join();
}

void RenderThread::Post(std::function<void()> job) {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    jobs_.push_back(std::move(job));
  }
  wake_.notify_one();
}

void RenderThread::Loop(std::function<void()> start, std::promise<void>* started) {
  try {
    start();
  } catch (...) {
    started->set_exception(std::current_exception());
    return;
  }
  started->set_value();
  for (;;) {
    std::function<void()> job;
    {
      std::unique_lock<std::mutex> lock(mutex_);
      wake_.wait(lock, [this] { return quit_ || !jobs_.empty(); });
      if (jobs_.empty()) break;  // quit only once the queue is drained
      job = std::move(jobs_.front());
      jobs_.pop_front();
    }
    job();  // packaged tasks keep their exceptions for the caller
  }
  if (stop_) stop_();
}

}  // namespace culinarycut::render

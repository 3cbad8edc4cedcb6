// tear: a thread of the host's that runs tasks in turn beside the calling thread, kept while its
// owner lives, so that the OpenMP threads its tasks start are made once.
#pragma once

#include <condition_variable>
#include <deque>
#include <future>
#include <mutex>
#include <thread>

namespace tear::backend {

/// Runs `std::packaged_task<R()>`s one after another on one thread of its own, started at the
/// first. A task's result or error lands in its future; the destructor waits for the task under
/// way and drops the ones not started.
template <class R>
class HostWorker {
 public:
  HostWorker() = default;
  HostWorker(const HostWorker&) = delete;
  HostWorker& operator=(const HostWorker&) = delete;
  ~HostWorker() {
    {
      const std::lock_guard<std::mutex> lock(mutex_);
      stop_ = true;
    }
    wake_.notify_one();
    if (thread_.joinable()) thread_.join();
  }

  /// Queues `task`; throws std::system_error where no thread can be started.
  void run(std::packaged_task<R()> task) {
    if (!thread_.joinable()) thread_ = std::thread([this] { loop(); });
    {
      const std::lock_guard<std::mutex> lock(mutex_);
      tasks_.push_back(std::move(task));
    }
    wake_.notify_one();
  }

 private:
  void loop() {
    for (;;) {
      std::packaged_task<R()> task;
      {
        std::unique_lock<std::mutex> lock(mutex_);
        wake_.wait(lock, [this] { return stop_ || !tasks_.empty(); });
        if (stop_) return;
        task = std::move(tasks_.front());
        tasks_.pop_front();
      }
      task();
    }
  }

  std::mutex mutex_;
  std::condition_variable wake_;
  std::deque<std::packaged_task<R()>> tasks_;
  bool stop_ = false;
  std::thread thread_;
};

}  // namespace tear::backend

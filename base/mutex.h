#pragma once

// A mutex and its lock that clang's thread-safety analysis understands (-Wthread-safety): shared state
// says which mutex guards it (DC_GUARDED_BY), functions which mutex they need held (DC_REQUIRES), and the
// compiler checks every access, where a comment could only ask. std::mutex carries no such annotations in
// libstdc++. scripts/thread-safety.sh runs the analysis; GCC builds see plain code.

#include <chrono>
#include <condition_variable>
#include <mutex>

#if defined(__clang__)
#define DC_THREAD_ANNOTATION(x) __attribute__((x))
#else
#define DC_THREAD_ANNOTATION(x)
#endif
#define DC_CAPABILITY(name) DC_THREAD_ANNOTATION(capability(name))
#define DC_SCOPED_CAPABILITY DC_THREAD_ANNOTATION(scoped_lockable)
#define DC_GUARDED_BY(mutex) DC_THREAD_ANNOTATION(guarded_by(mutex))
#define DC_REQUIRES(...) DC_THREAD_ANNOTATION(requires_capability(__VA_ARGS__))
#define DC_ACQUIRE(...) DC_THREAD_ANNOTATION(acquire_capability(__VA_ARGS__))
#define DC_TRY_ACQUIRE(...) DC_THREAD_ANNOTATION(try_acquire_capability(__VA_ARGS__))
#define DC_RELEASE(...) DC_THREAD_ANNOTATION(release_capability(__VA_ARGS__))
#define DC_EXCLUDES(...) DC_THREAD_ANNOTATION(locks_excluded(__VA_ARGS__))

namespace dc::base {

class MutexLock;

class DC_CAPABILITY("mutex") Mutex {
public:
    void lock() DC_ACQUIRE() { mutex_.lock(); }
    void unlock() DC_RELEASE() { mutex_.unlock(); }
    bool tryLock() DC_TRY_ACQUIRE(true) { return mutex_.try_lock(); }

private:
    friend class MutexLock;
    std::mutex mutex_;
};

// Holds a Mutex from construction to destruction, and waits on condition variables with it (released while
// waiting, held again when the wait returns, as the analysis assumes of a call that keeps it).
class DC_SCOPED_CAPABILITY MutexLock {
public:
    explicit MutexLock(Mutex& mutex) DC_ACQUIRE(mutex) : lock_(mutex.mutex_) {}
    ~MutexLock() DC_RELEASE() {}
    MutexLock(const MutexLock&) = delete;
    MutexLock& operator=(const MutexLock&) = delete;

    // Lets go of the mutex for a while (work done without it), and takes it again.
    void unlock() DC_RELEASE() { lock_.unlock(); }
    void lock() DC_ACQUIRE() { lock_.lock(); }

    // `ready` runs with the mutex held; annotate it DC_REQUIRES(the mutex) when it reads guarded state.
    template <class Ready> void wait(std::condition_variable& condition, Ready ready) {
        condition.wait(lock_, ready);
    }
    template <class Ready>
    bool waitFor(std::condition_variable& condition, std::chrono::milliseconds timeout, Ready ready) {
        return condition.wait_for(lock_, timeout, ready);
    }

private:
    std::unique_lock<std::mutex> lock_;
};

} // namespace dc::base

#pragma once

#include <string>
#include <sys/types.h>
#include <vector>

namespace dc::test {

// A child process started with posix_spawn and ended, with every process it started, when it goes out of
// scope: SIGINT first (roscore and rospy shut down their children on it), then SIGKILL for whatever of its
// process tree is still there after a grace period.
class ChildProcess {
public:
    ChildProcess() = default;
    ChildProcess(const std::vector<std::string>& argv, const std::string& logFile);
    ChildProcess(ChildProcess&& other) noexcept;
    ChildProcess& operator=(ChildProcess&& other) noexcept;
    ChildProcess(const ChildProcess&) = delete;
    ChildProcess& operator=(const ChildProcess&) = delete;
    ~ChildProcess() { stop(); }

    bool running() const { return pid_ > 0; }
    void stop();

private:
    pid_t pid_ = -1;
};

// A TCP port on 127.0.0.1 that nothing listened on a moment ago.
int freeLocalPort();

// Debian's roscore on 127.0.0.1:port, with ROS_HOME in `rosHome`. start() waits until the master answers.
class RosCore {
public:
    RosCore(int port, std::string rosHome) : port_(port), rosHome_(std::move(rosHome)) {}
    bool start();
    void stop() { process_.stop(); }
    std::string uri() const { return "http://127.0.0.1:" + std::to_string(port_); }
    int port() const { return port_; }
    std::string logFile() const { return rosHome_ + "/roscore.log"; }

private:
    int port_;
    std::string rosHome_;
    ChildProcess process_;
};

// Sets ROS_MASTER_URI, ROS_IP, ROS_HOSTNAME (127.0.0.1) and ROS_HOME for this process and its children.
void useLocalRosMaster(const std::string& uri, const std::string& rosHome);

} // namespace dc::test

#include "tests/ros/ros_processes.h"

#include "devices/ros/ros_master.h"

#include <chrono>
#include <csignal>
#include <cstdlib>
#include <dirent.h>
#include <fcntl.h>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <netinet/in.h>
#include <spawn.h>
#include <sys/socket.h>
#include <sys/wait.h>
#include <thread>
#include <unistd.h>

extern char** environ;

namespace dc::test {

namespace {

using namespace std::chrono_literals;

pid_t parentOf(pid_t pid) {
    std::ifstream in("/proc/" + std::to_string(pid) + "/stat");
    std::string text;
    std::getline(in, text);
    const auto close = text.rfind(')'); // the command name may hold spaces and parentheses
    if (close == std::string::npos)
        return -1;
    char state = 0;
    int ppid = -1;
    if (std::sscanf(text.c_str() + close + 1, " %c %d", &state, &ppid) != 2)
        return -1;
    return ppid;
}

// Every process below `root` (roslaunch starts its nodes in sessions of their own, so a process group
// would not reach them).
std::vector<pid_t> descendantsOf(pid_t root) {
    std::vector<pid_t> all;
    if (DIR* dir = ::opendir("/proc")) {
        while (const dirent* e = ::readdir(dir))
            if (const int pid = std::atoi(e->d_name); pid > 0)
                all.push_back(pid);
        ::closedir(dir);
    }
    std::vector<pid_t> found{root};
    for (std::size_t i = 0; i < found.size(); ++i)
        for (pid_t pid : all)
            if (parentOf(pid) == found[i])
                found.push_back(pid);
    found.erase(found.begin());
    return found;
}

bool alive(pid_t pid) {
    return ::kill(pid, 0) == 0;
}

} // namespace

ChildProcess::ChildProcess(const std::vector<std::string>& argv, const std::string& logFile) {
    std::vector<char*> args;
    for (const std::string& a : argv)
        args.push_back(const_cast<char*>(a.c_str()));
    args.push_back(nullptr);
    posix_spawn_file_actions_t actions;
    posix_spawn_file_actions_init(&actions);
    posix_spawn_file_actions_addopen(&actions, 1, logFile.c_str(), O_WRONLY | O_CREAT | O_APPEND, 0644);
    posix_spawn_file_actions_adddup2(&actions, 1, 2);
    posix_spawn_file_actions_addopen(&actions, 0, "/dev/null", O_RDONLY, 0);
    pid_t pid = -1;
    if (::posix_spawnp(&pid, args[0], &actions, nullptr, args.data(), environ) == 0)
        pid_ = pid;
    posix_spawn_file_actions_destroy(&actions);
}

ChildProcess::ChildProcess(ChildProcess&& other) noexcept : pid_(std::exchange(other.pid_, -1)) {}

ChildProcess& ChildProcess::operator=(ChildProcess&& other) noexcept {
    stop();
    pid_ = std::exchange(other.pid_, -1);
    return *this;
}

void ChildProcess::stop() {
    if (pid_ <= 0)
        return;
    const std::vector<pid_t> tree = descendantsOf(pid_);
    ::kill(pid_, SIGINT);
    const auto deadline = std::chrono::steady_clock::now() + 10s;
    int status = 0;
    while (::waitpid(pid_, &status, WNOHANG) == 0 && std::chrono::steady_clock::now() < deadline)
        std::this_thread::sleep_for(20ms);
    if (::waitpid(pid_, &status, WNOHANG) == 0) {
        ::kill(pid_, SIGKILL);
        ::waitpid(pid_, &status, 0);
    }
    for (pid_t child : tree) {
        const auto childDeadline = std::chrono::steady_clock::now() + 3s;
        while (alive(child) && std::chrono::steady_clock::now() < childDeadline)
            std::this_thread::sleep_for(20ms);
        if (alive(child))
            ::kill(child, SIGKILL);
    }
    pid_ = -1;
}

int freeLocalPort() {
    const int fd = ::socket(AF_INET, SOCK_STREAM, 0);
    sockaddr_in address{};
    address.sin_family = AF_INET;
    address.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    socklen_t length = sizeof address;
    int port = -1;
    if (fd >= 0 && ::bind(fd, reinterpret_cast<sockaddr*>(&address), sizeof address) == 0 &&
        ::getsockname(fd, reinterpret_cast<sockaddr*>(&address), &length) == 0)
        port = ntohs(address.sin_port);
    if (fd >= 0)
        ::close(fd);
    return port;
}

void useLocalRosMaster(const std::string& uri, const std::string& rosHome) {
    ::setenv("ROS_MASTER_URI", uri.c_str(), 1);
    ::setenv("ROS_IP", "127.0.0.1", 1);
    ::setenv("ROS_HOSTNAME", "127.0.0.1", 1);
    ::setenv("ROS_HOME", rosHome.c_str(), 1);
}

bool RosCore::start() {
    std::filesystem::remove(logFile());
    process_ = ChildProcess({"roscore", "-p", std::to_string(port_)}, logFile());
    if (!process_.running())
        return false;
    // roscore is up once its master answers and rosout has started (it says so in its log); a roscore
    // interrupted before that takes long to stop.
    const auto master = devices::ros::parseMasterUri(uri());
    const auto deadline = std::chrono::steady_clock::now() + 30s;
    while (std::chrono::steady_clock::now() < deadline) {
        std::ifstream log(logFile());
        const std::string text{std::istreambuf_iterator<char>(log), {}};
        if (text.find("started core service [/rosout]") != std::string::npos &&
            devices::ros::probeMaster(*master, 200ms))
            return true;
        std::this_thread::sleep_for(50ms);
    }
    return false;
}

} // namespace dc::test

#include "devices/ros/ros_master.h"

#include <cerrno>
#include <charconv>
#include <cstdlib>
#include <cstring>
#include <fcntl.h>
#include <netdb.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

namespace dc::devices::ros {

namespace {

// A socket closed on every path out of the probe.
class Socket {
public:
    explicit Socket(int fd) : fd_(fd) {}
    ~Socket() {
        if (fd_ >= 0)
            ::close(fd_);
    }
    Socket(const Socket&) = delete;
    Socket& operator=(const Socket&) = delete;
    int get() const { return fd_; }

private:
    int fd_;
};

// 0 when connected within `timeout`, else an errno value (ETIMEDOUT when the time ran out).
int connectWithin(const addrinfo& address, std::chrono::milliseconds timeout) {
    Socket socket(
        ::socket(address.ai_family, address.ai_socktype | SOCK_NONBLOCK | SOCK_CLOEXEC, address.ai_protocol));
    if (socket.get() < 0)
        return errno;
    if (::connect(socket.get(), address.ai_addr, address.ai_addrlen) == 0)
        return 0;
    if (errno != EINPROGRESS)
        return errno;
    pollfd p{socket.get(), POLLOUT, 0};
    int r = 0;
    do {
        r = ::poll(&p, 1, static_cast<int>(timeout.count()));
    } while (r < 0 && errno == EINTR);
    if (r == 0)
        return ETIMEDOUT;
    if (r < 0)
        return errno;
    int error = 0;
    socklen_t length = sizeof error;
    if (::getsockopt(socket.get(), SOL_SOCKET, SO_ERROR, &error, &length) < 0)
        return errno;
    return error;
}

} // namespace

Expected<MasterUri> parseMasterUri(const std::string& uri) {
    const Error bad{"ROS master URI '" + uri + "' is not http://HOST:PORT"};
    const std::string scheme = "http://";
    if (uri.rfind(scheme, 0) != 0)
        return bad;
    std::string rest = uri.substr(scheme.size());
    if (!rest.empty() && rest.back() == '/')
        rest.pop_back();
    const auto colon = rest.rfind(':');
    if (colon == std::string::npos || colon == 0)
        return bad;
    MasterUri master{uri, rest.substr(0, colon), 0};
    const std::string port = rest.substr(colon + 1);
    const auto [end, ec] = std::from_chars(port.data(), port.data() + port.size(), master.port);
    if (port.empty() || ec != std::errc() || end != port.data() + port.size() || master.port <= 0 ||
        master.port > 65535)
        return bad;
    return master;
}

Expected<MasterUri> resolveMasterUri(const std::string& explicitUri) {
    if (!explicitUri.empty())
        return parseMasterUri(explicitUri);
    const char* env = std::getenv("ROS_MASTER_URI");
    if (env == nullptr || *env == '\0')
        return Error{"no ROS master: set ROS_MASTER_URI or add master=http://HOST:PORT to the source"};
    return parseMasterUri(env);
}

Status probeMaster(const MasterUri& master, std::chrono::milliseconds timeout) {
    addrinfo hints{};
    hints.ai_family = AF_UNSPEC;
    hints.ai_socktype = SOCK_STREAM;
    addrinfo* found = nullptr;
    const std::string port = std::to_string(master.port);
    if (const int r = ::getaddrinfo(master.host.c_str(), port.c_str(), &hints, &found); r != 0)
        return Error{"ROS master " + master.uri + " is not reachable: " + ::gai_strerror(r)};
    int error = ENOENT;
    for (const addrinfo* a = found; a != nullptr && error != 0; a = a->ai_next)
        error = connectWithin(*a, timeout);
    ::freeaddrinfo(found);
    if (error != 0)
        return Error{"ROS master " + master.uri + " is not reachable: " + std::strerror(error)};
    return {};
}

} // namespace dc::devices::ros

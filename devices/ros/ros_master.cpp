#include "devices/ros/ros_master.h"

#include "base/unique_fd.h"

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

using Clock = std::chrono::steady_clock;

// Waits for `events` on `fd` until `deadline`: 0 when ready, else an errno value (ETIMEDOUT at the deadline).
int waitFor(int fd, short events, Clock::time_point deadline) {
    const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(deadline - Clock::now());
    if (left.count() <= 0)
        return ETIMEDOUT;
    pollfd p{fd, events, 0};
    int r = 0;
    do {
        r = ::poll(&p, 1, static_cast<int>(left.count()));
    } while (r < 0 && errno == EINTR);
    if (r == 0)
        return ETIMEDOUT;
    return r < 0 ? errno : 0;
}

// 0 when connected before `deadline`, else an errno value.
int connectBefore(const base::UniqueFd& socket, const addrinfo& address, Clock::time_point deadline) {
    if (socket.get() < 0)
        return errno;
    if (::connect(socket.get(), address.ai_addr, address.ai_addrlen) == 0)
        return 0;
    if (errno != EINPROGRESS)
        return errno;
    if (const int r = waitFor(socket.get(), POLLOUT, deadline); r != 0)
        return r;
    int error = 0;
    socklen_t length = sizeof error;
    if (::getsockopt(socket.get(), SOL_SOCKET, SO_ERROR, &error, &length) < 0)
        return errno;
    return error;
}

// The master's cheapest XML-RPC call (getPid), as roscpp would send it.
std::string getPidRequest(const MasterUri& master) {
    const std::string body =
        "<?xml version=\"1.0\"?><methodCall><methodName>getPid</methodName><params><param>"
        "<value><string>/depthcloud_probe</string></value></param></params></methodCall>";
    return "POST / HTTP/1.1\r\nHost: " + master.host + ":" + std::to_string(master.port) +
           "\r\nContent-Type: text/xml\r\nContent-Length: " + std::to_string(body.size()) + "\r\n\r\n" + body;
}

// Something that accepts connections is not yet a master (a proxy, another server): it must answer an
// XML-RPC call with HTTP 200 before the deadline.
Status askForPid(const base::UniqueFd& socket, const MasterUri& master, Clock::time_point deadline) {
    const std::string request = getPidRequest(master);
    if (::send(socket.get(), request.data(), request.size(), MSG_NOSIGNAL) !=
        static_cast<ssize_t>(request.size()))
        return Error{"ROS master " + master.uri + " is not reachable: " + std::strerror(errno)};
    std::string reply;
    while (reply.find("\r\n") == std::string::npos) {
        if (const int r = waitFor(socket.get(), POLLIN, deadline); r != 0)
            return Error{"ROS master " + master.uri +
                         " is not reachable: it accepts connections but does not answer (" +
                         std::strerror(r) + ")"};
        char buffer[512];
        const ssize_t n = ::recv(socket.get(), buffer, sizeof buffer, 0);
        if (n <= 0)
            return Error{"ROS master " + master.uri +
                         " is not reachable: it closed the connection unanswered"};
        reply.append(buffer, static_cast<std::size_t>(n));
    }
    if (reply.rfind("HTTP/1.", 0) != 0 || reply.find(" 200 ") == std::string::npos)
        return Error{"ROS master " + master.uri + " is not reachable: what answers there is no ROS master (" +
                     reply.substr(0, reply.find("\r\n")) + ")"};
    return {};
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
    const auto deadline = Clock::now() + timeout;
    addrinfo hints{};
    hints.ai_family = AF_UNSPEC;
    hints.ai_socktype = SOCK_STREAM;
    addrinfo* found = nullptr;
    const std::string port = std::to_string(master.port);
    if (const int r = ::getaddrinfo(master.host.c_str(), port.c_str(), &hints, &found); r != 0)
        return Error{"ROS master " + master.uri + " is not reachable: " + ::gai_strerror(r)};
    Status status = Error{"ROS master " + master.uri + " is not reachable: no address"};
    for (const addrinfo* a = found; a != nullptr && !status; a = a->ai_next) {
        const base::UniqueFd socket(
            ::socket(a->ai_family, a->ai_socktype | SOCK_NONBLOCK | SOCK_CLOEXEC, a->ai_protocol));
        if (const int error = connectBefore(socket, *a, deadline); error != 0)
            status = Error{"ROS master " + master.uri + " is not reachable: " + std::strerror(error)};
        else
            status = askForPid(socket, master, deadline);
    }
    ::freeaddrinfo(found);
    return status;
}

} // namespace dc::devices::ros

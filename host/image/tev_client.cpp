#include "image/tev_client.h"

#include <fcntl.h>
#include <fmt/format.h>
#include <netdb.h>
#include <poll.h>
#include <sys/socket.h>
#include <sys/time.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <charconv>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <utility>

#include "input_error.h"

namespace vkpath::image {
namespace {

constexpr uint8_t CREATE_IMAGE = 4;
constexpr uint8_t UPDATE_IMAGE_V3 = 6;
// Pixels per update packet (about 768 KiB of floats): tev reads a packet
// whole before it shows any of it.
constexpr uint32_t BAND_PIXELS = 65536;
constexpr int CONNECT_TIMEOUT_MS = 500;
constexpr int SEND_TIMEOUT_SECONDS = 2;  // a viewer that stops reading counts as gone
constexpr auto RETRY_INTERVAL = std::chrono::seconds(1);

// tev's packet: the length first (filled in by finish), then the fields.
class Packet {
  public:
    explicit Packet(uint8_t type) : m_bytes(4, 0) { m_bytes.push_back(type); }
    void boolean(bool v) { m_bytes.push_back(v ? 1 : 0); }
    void string(const std::string& v) {
        m_bytes.insert(m_bytes.end(), v.begin(), v.end());
        m_bytes.push_back(0);
    }
    template <typename T>
    void number(T v) {  // little-endian, as on every host vkpath builds for
        const auto* p = reinterpret_cast<const uint8_t*>(&v);
        m_bytes.insert(m_bytes.end(), p, p + sizeof(T));
    }
    std::vector<uint8_t> finish() {
        const uint32_t size = uint32_t(m_bytes.size());
        std::memcpy(m_bytes.data(), &size, sizeof(size));
        return std::move(m_bytes);
    }

  private:
    std::vector<uint8_t> m_bytes;
};

const char* const CHANNELS[3] = {"R", "G", "B"};

// Whether the viewer closed the connection (tev sends nothing to a client, so
// anything readable is its end).
bool peerClosed(int socket) {
    pollfd p{socket, POLLIN | POLLRDHUP, 0};
    if (poll(&p, 1, 0) != 1) return false;
    if (p.revents & (POLLHUP | POLLRDHUP | POLLERR)) return true;
    char byte;
    return recv(socket, &byte, 1, MSG_PEEK | MSG_DONTWAIT) == 0;
}

}  // namespace

DisplayServer parseDisplayServer(const std::string& text, const std::string& flag) {
    const size_t colon = text.rfind(':');
    const auto bad = [&](const std::string& why) {
        return InputError(fmt::format("{} '{}': {}", flag, text, why));
    };
    if (colon == std::string::npos || colon == 0) throw bad("not HOST:PORT");
    DisplayServer server;
    server.host = text.substr(0, colon);
    unsigned port = 0;
    const char* begin = text.data() + colon + 1;
    const char* end = text.data() + text.size();
    const auto [last, ec] = std::from_chars(begin, end, port);
    if (ec != std::errc() || last != end || port == 0 || port > 65535)
        throw bad("the port is not a number in 1..65535");
    server.port = uint16_t(port);
    return server;
}

std::vector<uint8_t> tevCreateImagePacket(const std::string& name, uint32_t width,
                                          uint32_t height) {
    Packet p(CREATE_IMAGE);
    p.boolean(false);  // grab focus
    p.string(name);
    p.number(int32_t(width));
    p.number(int32_t(height));
    p.number(int32_t(3));
    for (const char* channel : CHANNELS) p.string(channel);
    return p.finish();
}

std::vector<uint8_t> tevUpdateImagePacket(const std::string& name, const Image& image, uint32_t y0,
                                          uint32_t rows) {
    Packet p(UPDATE_IMAGE_V3);
    p.boolean(false);
    p.string(name);
    p.number(int32_t(3));
    for (const char* channel : CHANNELS) p.string(channel);
    p.number(int32_t(0));
    p.number(int32_t(y0));
    p.number(int32_t(image.width));
    p.number(int32_t(rows));
    for (int64_t c = 0; c < 3; ++c) p.number(c);       // offsets
    for (int c = 0; c < 3; ++c) p.number(int64_t(3));  // strides: RGB interleaved
    for (uint32_t y = y0; y < y0 + rows; ++y)
        for (uint32_t x = 0; x < image.width; ++x)
            for (int c = 0; c < 3; ++c) p.number(image.pixels[size_t(y) * image.width + x][c]);
    return p.finish();
}

TevClient::TevClient(DisplayServer server, std::string imageName)
    : m_server(std::move(server)), m_name(std::move(imageName)), m_thread([this] { run(); }) {}

TevClient::~TevClient() {
    {
        const std::lock_guard lock(m_mutex);
        m_quit = true;
    }
    m_changed.notify_all();
    m_thread.join();
    disconnect();
}

void TevClient::show(Image image) {
    {
        const std::lock_guard lock(m_mutex);
        m_pending = std::move(image);
    }
    m_changed.notify_all();
}

void TevClient::finish(double seconds) {
    std::unique_lock lock(m_mutex);
    m_changed.wait_for(lock, std::chrono::duration<double>(seconds),
                       [&] { return !m_pending && !m_busy; });
}

void TevClient::run() {
    std::unique_lock lock(m_mutex);
    while (true) {
        m_changed.wait(lock, [&] { return m_quit || m_pending; });
        if (m_quit) break;
        Image image = std::move(*m_pending);
        m_pending.reset();
        m_busy = true;
        lock.unlock();
        const bool sent = send(image);
        lock.lock();
        m_busy = false;
        if (!sent && !m_pending) m_pending = std::move(image);  // again, unless a newer came
        m_changed.notify_all();
        if (!sent) m_changed.wait_for(lock, RETRY_INTERVAL, [&] { return m_quit; });
    }
}

bool TevClient::send(const Image& image) {
    if (m_socket >= 0 && peerClosed(m_socket)) {
        warnOnce("the viewer closed the connection");
        disconnect();
    }
    if (m_socket < 0) {
        if (!connect()) return false;
        if (!sendAll(tevCreateImagePacket(m_name, image.width, image.height))) return false;
    }
    const uint32_t rows = std::max<uint32_t>(1, BAND_PIXELS / std::max<uint32_t>(image.width, 1));
    for (uint32_t y = 0; y < image.height; y += rows)
        if (!sendAll(tevUpdateImagePacket(m_name, image, y, std::min(rows, image.height - y))))
            return false;
    return true;
}

bool TevClient::connect() {
    addrinfo hints{};
    hints.ai_family = AF_UNSPEC;
    hints.ai_socktype = SOCK_STREAM;
    addrinfo* found = nullptr;
    const std::string port = std::to_string(m_server.port);
    if (const int err = getaddrinfo(m_server.host.c_str(), port.c_str(), &hints, &found)) {
        warnOnce(gai_strerror(err));
        return false;
    }
    std::string failure = "no address";
    for (addrinfo* a = found; a && m_socket < 0; a = a->ai_next) {
        const int fd = socket(a->ai_family, a->ai_socktype | SOCK_CLOEXEC, a->ai_protocol);
        if (fd < 0) continue;
        // Connect without blocking for longer than CONNECT_TIMEOUT_MS.
        fcntl(fd, F_SETFL, fcntl(fd, F_GETFL, 0) | O_NONBLOCK);
        int error = 0;
        if (::connect(fd, a->ai_addr, a->ai_addrlen) != 0) {
            error = errno;
            if (error == EINPROGRESS) {
                pollfd p{fd, POLLOUT, 0};
                error = ETIMEDOUT;
                if (poll(&p, 1, CONNECT_TIMEOUT_MS) == 1) {
                    socklen_t length = sizeof(error);
                    getsockopt(fd, SOL_SOCKET, SO_ERROR, &error, &length);
                }
            }
        }
        if (error != 0) {
            failure = std::strerror(error);
            close(fd);
            continue;
        }
        fcntl(fd, F_SETFL, fcntl(fd, F_GETFL, 0) & ~O_NONBLOCK);
        const timeval timeout{SEND_TIMEOUT_SECONDS, 0};
        setsockopt(fd, SOL_SOCKET, SO_SNDTIMEO, &timeout, sizeof(timeout));
        m_socket = fd;
    }
    freeaddrinfo(found);
    if (m_socket < 0) warnOnce(failure);
    return m_socket >= 0;
}

bool TevClient::sendAll(const std::vector<uint8_t>& bytes) {
    size_t done = 0;
    while (done < bytes.size()) {
        const ssize_t n = ::send(m_socket, bytes.data() + done, bytes.size() - done, MSG_NOSIGNAL);
        if (n <= 0) {
            if (n < 0 && errno == EINTR) continue;
            warnOnce(n < 0 ? std::strerror(errno) : "the connection closed");
            disconnect();
            return false;
        }
        done += size_t(n);
    }
    return true;
}

void TevClient::disconnect() {
    if (m_socket >= 0) close(m_socket);
    m_socket = -1;
}

void TevClient::warnOnce(const std::string& what) {
    if (m_warned) return;
    m_warned = true;
    std::fprintf(stderr,
                 "vkpath: warning: --display-server %s:%u: %s; the render goes on, and the image "
                 "is sent when the viewer can be reached (tried again every second)\n",
                 m_server.host.c_str(), unsigned(m_server.port), what.c_str());
}

}  // namespace vkpath::image

// A render in progress, shown in the tev image viewer (Tom94/tev) over its
// TCP protocol, as pbrt-v4's --display-server does: the image is created in
// tev once (per connection) and then updated in bands of rows.
//
// The wire format (tev's include/tev/Ipc.h): a packet is its own length as a
// little-endian uint32 (these four bytes included), a type byte, then fields:
// bools as one byte, strings NUL-terminated, integers and floats
// little-endian, arrays element after element. CreateImage (4): grab focus,
// name, width, height (int32), channel count (int32), channel names.
// UpdateImageV3 (6): grab focus, name, channel count, channel names, x, y,
// width, height (int32), per channel an int64 offset and an int64 stride
// into the floats that follow.
//
// Sending never holds up the render: show() hands the latest image to a
// thread of the client's own, which sends the newest it has (older ones are
// dropped), connects when it has something to send (again, with the image
// created anew, when the viewer has closed the connection since the last),
// and after a failure (tev not running yet, or gone) tries again at most once
// a second. The first failure is one warning line; later ones are silent.
#pragma once

#include <condition_variable>
#include <cstdint>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "image/image.h"

namespace vkpath::image {

// HOST:PORT, checked: throws InputError naming `flag` when it is not a host
// and a port in 1..65535.
struct DisplayServer {
    std::string host;
    uint16_t port = 0;
};
DisplayServer parseDisplayServer(const std::string& text, const std::string& flag);

// The packets, for the client and for tests.
std::vector<uint8_t> tevCreateImagePacket(const std::string& name, uint32_t width, uint32_t height);
// Rows [y0, y0 + rows) of `image`, as R, G and B channels interleaved.
std::vector<uint8_t> tevUpdateImagePacket(const std::string& name, const Image& image, uint32_t y0,
                                          uint32_t rows);

class TevClient {
  public:
    TevClient(DisplayServer server, std::string imageName);
    // Ends the thread after the send in progress (finish() first to wait for the last image).
    ~TevClient();
    TevClient(const TevClient&) = delete;
    TevClient& operator=(const TevClient&) = delete;

    // Queues `image` to be sent (replacing one not yet sent); returns at once.
    void show(Image image);
    // Sends the last image shown, waiting for it up to `seconds`.
    void finish(double seconds);

  private:
    void run();
    bool send(const Image& image);  // connects first where needed
    bool sendAll(const std::vector<uint8_t>& bytes);
    bool connect();
    void disconnect();
    void warnOnce(const std::string& what);

    DisplayServer m_server;
    std::string m_name;
    std::mutex m_mutex;
    std::condition_variable m_changed;
    std::optional<Image> m_pending;  // the newest image not yet taken by the thread
    bool m_busy = false;             // the thread is sending an image
    bool m_quit = false;
    int m_socket = -1;
    bool m_warned = false;
    std::thread m_thread;
};

}  // namespace vkpath::image

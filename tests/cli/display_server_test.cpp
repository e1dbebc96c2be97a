// render --display-server: the render shown in tev as it goes. A small server
// written here speaks the viewer's side of tev's protocol (its
// include/tev/Ipc.h: length-prefixed packets, CreateImage and UpdateImageV3)
// and decodes what vkpath sends; the last image it holds must be the EXR's
// pixels bit for bit, and a viewer that goes away is reconnected to.
#include <arpa/inet.h>
#include <gtest/gtest.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cstring>
#include <filesystem>
#include <map>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "image/image.h"
#include "image/tev_client.h"
#include "input_error.h"
#include "support/run_vkpath.h"
#include "support/temp_dir.h"
#include "support/test_context.h"

namespace {

using namespace vkpath;

// What the viewer holds: each image by name, as the packets built it.
struct ViewerImage {
    int32_t width = 0, height = 0;
    std::vector<std::string> channels;
    std::vector<float> rgb;  // interleaved, as CreateImage made it and updates filled it
    int updates = 0;         // UpdateImage packets
    int fullUpdates = 0;     // of them, those that covered the last row (a whole image sent)
};

// Reads packets the way tev's IStream does; a malformed one fails the test.
class PacketReader {
  public:
    explicit PacketReader(std::vector<uint8_t> bytes) : m_bytes(std::move(bytes)) {}
    template <typename T>
    T number() {
        T v{};
        if (m_at + sizeof(T) > m_bytes.size()) throw std::runtime_error("packet overrun");
        std::memcpy(&v, m_bytes.data() + m_at, sizeof(T));
        m_at += sizeof(T);
        return v;
    }
    std::string string() {
        std::string s;
        while (true) {
            const char c = number<char>();
            if (c == '\0') return s;
            s += c;
        }
    }
    bool done() const { return m_at == m_bytes.size(); }

  private:
    std::vector<uint8_t> m_bytes;
    size_t m_at = 0;
};

class FakeTev {
  public:
    // closeFirstAfterImage: the viewer closes the first connection once it
    // has the first whole image (a viewer that goes away).
    explicit FakeTev(bool closeFirstAfterImage = false) : m_closeFirst(closeFirstAfterImage) {
        m_listen = socket(AF_INET, SOCK_STREAM, 0);
        sockaddr_in address{};
        address.sin_family = AF_INET;
        address.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
        address.sin_port = 0;
        EXPECT_EQ(bind(m_listen, reinterpret_cast<sockaddr*>(&address), sizeof(address)), 0);
        EXPECT_EQ(listen(m_listen, 4), 0);
        socklen_t length = sizeof(address);
        getsockname(m_listen, reinterpret_cast<sockaddr*>(&address), &length);
        m_port = ntohs(address.sin_port);
        m_thread = std::thread([this] { serve(); });
    }
    ~FakeTev() {
        shutdown(m_listen, SHUT_RDWR);
        close(m_listen);
        m_thread.join();
    }
    std::string address() const { return "127.0.0.1:" + std::to_string(m_port); }
    int connections() const { return m_connections; }
    int creates() const { return m_creates; }
    ViewerImage image(const std::string& name) {
        const std::lock_guard lock(m_mutex);
        return m_images[name];
    }
    std::string error() {
        const std::lock_guard lock(m_mutex);
        return m_error;
    }

  private:
    void serve() {
        while (true) {
            const int fd = accept(m_listen, nullptr, nullptr);
            if (fd < 0) return;
            const int connection = ++m_connections;
            try {
                readPackets(fd, connection == 1 && m_closeFirst);
            } catch (const std::exception& e) {
                const std::lock_guard lock(m_mutex);
                m_error = e.what();
            }
            close(fd);
        }
    }

    bool readAll(int fd, uint8_t* data, size_t size) {
        size_t done = 0;
        while (done < size) {
            const ssize_t n = recv(fd, data + done, size - done, 0);
            if (n <= 0) return false;
            done += size_t(n);
        }
        return true;
    }

    void readPackets(int fd, bool closeAfterImage) {
        while (true) {
            uint32_t size = 0;
            if (!readAll(fd, reinterpret_cast<uint8_t*>(&size), 4)) return;
            if (size < 5) throw std::runtime_error("a packet shorter than its header");
            std::vector<uint8_t> bytes(size);
            std::memcpy(bytes.data(), &size, 4);
            if (!readAll(fd, bytes.data() + 4, size - 4)) throw std::runtime_error("cut packet");
            PacketReader p(std::move(bytes));
            p.number<uint32_t>();
            const uint8_t type = p.number<uint8_t>();
            const bool grabFocus = p.number<uint8_t>() != 0;
            (void)grabFocus;
            const std::string name = p.string();
            const std::lock_guard lock(m_mutex);
            if (type == 4) {  // CreateImage
                ViewerImage& image = m_images[name];
                image.width = p.number<int32_t>();
                image.height = p.number<int32_t>();
                const int32_t channels = p.number<int32_t>();
                image.channels.clear();
                for (int32_t c = 0; c < channels; ++c) image.channels.push_back(p.string());
                image.rgb.assign(size_t(image.width) * image.height * 3, -1.0f);
                ++m_creates;
                if (!p.done()) throw std::runtime_error("CreateImage: bytes left over");
            } else if (type == 6) {  // UpdateImageV3
                ViewerImage& image = m_images.at(name);
                const int32_t channels = p.number<int32_t>();
                std::vector<std::string> names;
                for (int32_t c = 0; c < channels; ++c) names.push_back(p.string());
                const int32_t x = p.number<int32_t>(), y = p.number<int32_t>();
                const int32_t w = p.number<int32_t>(), h = p.number<int32_t>();
                std::vector<int64_t> offsets, strides;
                for (int32_t c = 0; c < channels; ++c) offsets.push_back(p.number<int64_t>());
                for (int32_t c = 0; c < channels; ++c) strides.push_back(p.number<int64_t>());
                size_t floats = 0;
                for (int32_t c = 0; c < channels; ++c)
                    floats = std::max<size_t>(
                        floats, size_t(offsets[c] + (int64_t(w) * h - 1) * strides[c] + 1));
                std::vector<float> data(floats);
                for (float& v : data) v = p.number<float>();
                if (!p.done()) throw std::runtime_error("UpdateImage: bytes left over");
                if (x < 0 || y < 0 || x + w > image.width || y + h > image.height)
                    throw std::runtime_error("UpdateImage outside the image");
                for (int32_t c = 0; c < channels; ++c) {
                    const size_t channel =
                        size_t(std::find(image.channels.begin(), image.channels.end(), names[c]) -
                               image.channels.begin());
                    if (channel >= 3) throw std::runtime_error("an unknown channel " + names[c]);
                    for (int32_t py = 0; py < h; ++py)
                        for (int32_t px = 0; px < w; ++px)
                            image.rgb[(size_t(y + py) * image.width + x + px) * 3 + channel] =
                                data[size_t(offsets[c] + (int64_t(py) * w + px) * strides[c])];
                }
                ++image.updates;
                image.fullUpdates += y + h == image.height;
                if (closeAfterImage && y + h == image.height) return;
            } else {
                throw std::runtime_error("unexpected packet type " + std::to_string(type));
            }
        }
    }

    bool m_closeFirst;
    int m_listen = -1;
    uint16_t m_port = 0;
    std::atomic<int> m_connections{0}, m_creates{0};
    std::mutex m_mutex;
    std::map<std::string, ViewerImage> m_images;
    std::string m_error;
    std::thread m_thread;
};

void expectTheExr(const ViewerImage& shown, const std::filesystem::path& exr) {
    const image::Image written = image::readImage(exr);
    ASSERT_EQ(shown.width, int32_t(written.width));
    ASSERT_EQ(shown.height, int32_t(written.height));
    EXPECT_EQ(shown.channels, (std::vector<std::string>{"R", "G", "B"}));
    size_t differing = 0;
    for (size_t i = 0; i < written.pixels.size(); ++i)
        for (int c = 0; c < 3; ++c) differing += shown.rgb[i * 3 + c] != written.pixels[i][c];
    EXPECT_EQ(differing, 0u) << "of " << written.pixels.size() * 3 << " values";
}

std::string box() {
    return test::sourcePath("assets/cornell_box.gltf").string();
}

// The viewer gets the image created once, updates while the render runs (a
// 1.5 s budget: at most every 0.25 s, at wave ends) and at the end the EXR's
// pixels, bit for bit; on the GPU (in waves of 20 000 paths, so that several
// end within the budget) and on the CPU reference. The 640 x 120 film takes
// two bands of rows an update.
TEST(DisplayServer, TheViewerEndsWithTheExrsPixels) {
    const test::TempDir dir;
    for (const char* device : {"gpu", "cpu"}) {
        SCOPED_TRACE(device);
        FakeTev tev;
        const auto exr = dir / (std::string(device) + ".exr");
        const std::string waves = std::string(device) == "gpu" ? " --paths-in-flight 20000" : "";
        const auto r = test::runVkpath(
            "render " + box() + " --device " + device + " -d 640x120 --time-budget 1.5" + waves +
            " --display-server " + tev.address() + " -o " + exr.string());
        ASSERT_EQ(r.exitCode, 0) << r.err;
        EXPECT_EQ(tev.error(), "");
        EXPECT_EQ(tev.connections(), 1);
        EXPECT_EQ(tev.creates(), 1);
        const ViewerImage shown = tev.image(exr.filename().string());
        EXPECT_GE(shown.fullUpdates, 2) << "a preview and the final image";
        EXPECT_EQ(shown.updates, 2 * shown.fullUpdates) << "bands of 102 rows of 640";
        expectTheExr(shown, exr);
    }
}

// A viewer that goes away (closes the connection once it has the first
// image): the render goes on, says so in one warning line, connects again
// for the next image and creates it anew, and the viewer still ends with the
// EXR's pixels.
TEST(DisplayServer, AViewerThatGoesAwayIsReconnectedTo) {
    const test::TempDir dir;
    FakeTev tev(true);
    const auto exr = dir / "box.exr";
    const auto r = test::runVkpath("render " + box() +
                                   " -d 64x48 --time-budget 1.5 --paths-in-flight 1024 "
                                   "--display-server " +
                                   tev.address() + " -o " + exr.string());
    ASSERT_EQ(r.exitCode, 0) << r.err;
    EXPECT_EQ(tev.error(), "");
    EXPECT_EQ(tev.connections(), 2);
    EXPECT_EQ(tev.creates(), 2);
    EXPECT_NE(r.err.find("vkpath: warning: --display-server " + tev.address()), std::string::npos)
        << r.err;
    expectTheExr(tev.image("box.exr"), exr);
}

// No viewer at all: one warning line, and the render and its EXR as without
// the flag. A HOST:PORT that is not one: one line, exit code 2, nothing written.
TEST(DisplayServer, NoViewerIsAWarningAndABadAddressIsOneLine) {
    const test::TempDir dir;
    const auto exr = dir / "box.exr";
    int unused = 0;
    {
        FakeTev closed;  // a port that was listening and is not any more
        unused = std::stoi(closed.address().substr(closed.address().rfind(':') + 1));
    }
    const auto r = test::runVkpath(
        "render " + box() + " -d 16x12 -s 4 --display-server 127.0.0.1:" + std::to_string(unused) +
        " -o " + exr.string());
    EXPECT_EQ(r.exitCode, 0) << r.err;
    EXPECT_TRUE(std::filesystem::exists(exr));
    size_t warnings = 0;
    for (size_t at = r.err.find("--display-server"); at != std::string::npos;
         at = r.err.find("--display-server", at + 1))
        ++warnings;
    EXPECT_EQ(warnings, 1u) << r.err;
    for (const char* bad :
         {"localhost", ":14158", "localhost:0", "localhost:65536", "localhost:port"}) {
        SCOPED_TRACE(bad);
        const auto b = test::runVkpath("render " + box() + " -d 16x12 -s 4 --display-server '" +
                                       std::string(bad) + "' -o " + (dir / "bad.exr").string());
        EXPECT_EQ(b.exitCode, 2) << b.err;
        EXPECT_EQ(test::lineCount(b.err), 1) << b.err;
        EXPECT_FALSE(std::filesystem::exists(dir / "bad.exr"));
    }
}

// The packets as tev's reader takes them: the length first (all of it),
// then the type and the fields.
TEST(DisplayServer, PacketsAreTevsLayout) {
    const std::vector<uint8_t> create = image::tevCreateImagePacket("a.exr", 3, 2);
    uint32_t size = 0;
    std::memcpy(&size, create.data(), 4);
    EXPECT_EQ(size, create.size());
    const std::vector<uint8_t> expected = {0,   0, 0, 0, 4,   0, 'a', '.', 'e', 'x',
                                           'r', 0, 3, 0, 0,   0, 2,   0,   0,   0,
                                           3,   0, 0, 0, 'R', 0, 'G', 0,   'B', 0};
    EXPECT_EQ(std::vector<uint8_t>(create.begin() + 4, create.end()),
              std::vector<uint8_t>(expected.begin() + 4, expected.end()));
    image::Image picture(3, 2);
    picture.at(2, 1) = {1.0f, 2.0f, 3.0f};
    const std::vector<uint8_t> update = image::tevUpdateImagePacket("a.exr", picture, 1, 1);
    // type, focus, name, 3 channels and their names, x y w h, 3 offsets and
    // 3 strides of 8 bytes, 3 pixels of 3 floats.
    EXPECT_EQ(update.size(), 4u + 1 + 1 + 6 + 4 + 6 + 16 + 48 + 36);
    float last[3];
    std::memcpy(last, update.data() + update.size() - 12, 12);
    EXPECT_EQ(last[0], 1.0f);
    EXPECT_EQ(last[2], 3.0f);
    EXPECT_THROW(image::parseDisplayServer("x", "--display-server"), InputError);
}

}  // namespace

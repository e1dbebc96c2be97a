#include "app/stop_signal.h"

#include <unistd.h>

#include <csignal>

namespace vkpath::app {
namespace {

volatile std::sig_atomic_t g_signal = 0;
struct sigaction g_previousInt, g_previousTerm;

// Only async-signal-safe calls: write and _exit.
void onSignal(int signal) {
    if (g_signal != 0) _exit(128 + signal);
    g_signal = signal;
    const char message[] =
        "\nvkpath: stopping at the next whole sample (signal again to quit at once)\n";
    [[maybe_unused]] const ssize_t n = write(STDERR_FILENO, message, sizeof(message) - 1);
}

}  // namespace

StopOnSignal::StopOnSignal() {
    g_signal = 0;
    struct sigaction action {};
    action.sa_handler = onSignal;
    sigemptyset(&action.sa_mask);
    action.sa_flags = SA_RESTART;
    sigaction(SIGINT, &action, &g_previousInt);
    sigaction(SIGTERM, &action, &g_previousTerm);
}

StopOnSignal::~StopOnSignal() {
    sigaction(SIGINT, &g_previousInt, nullptr);
    sigaction(SIGTERM, &g_previousTerm, nullptr);
}

int StopOnSignal::requested() {
    return g_signal;
}

}  // namespace vkpath::app

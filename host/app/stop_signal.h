// SIGINT and SIGTERM during a render: the first asks the render to stop at
// the next whole sample (the caller then writes the image so far and its
// checkpoint, and exits with 128 + the signal: 130 or 143); a second one
// exits at once with that code, writing nothing more (the outputs are
// written beside their paths and renamed, so none is left half-written).
#pragma once

namespace vkpath::app {

class StopOnSignal {
  public:
    // Installs the handlers; the destructor puts back the ones before.
    StopOnSignal();
    ~StopOnSignal();
    StopOnSignal(const StopOnSignal&) = delete;
    StopOnSignal& operator=(const StopOnSignal&) = delete;

    // The signal that asked for a stop, or 0.
    static int requested();
};

}  // namespace vkpath::app

// Runs the built vkpath executable as a user would and captures what it says.
#pragma once

#include <string>

namespace vkpath::test {

struct CommandResult {
    int exitCode = -1;
    std::string out;  // stdout
    std::string err;  // stderr
    bool timedOut = false;
};

// `args` is appended to the vkpath path as-is (shell syntax). With a
// `timeoutSeconds` > 0, vkpath is killed past it (coreutils `timeout`, SIGKILL
// 5 s after a SIGTERM it ignores) and `timedOut` is set.
CommandResult runVkpath(const std::string& args, int timeoutSeconds = 0);

// vkpath started in the background (for tests that signal it while it runs).
class RunningVkpath {
  public:
    explicit RunningVkpath(const std::string& args);
    ~RunningVkpath();  // kills it if still running
    RunningVkpath(const RunningVkpath&) = delete;
    RunningVkpath& operator=(const RunningVkpath&) = delete;

    void signal(int signal) const;
    std::string err() const;  // stderr so far
    // Waits for the exit (128 + the signal if a signal ended it).
    CommandResult wait();

  private:
    std::string m_dir;
    int m_pid = -1;
};

// The number of lines in `text` (a last line without '\n' counts).
int lineCount(const std::string& text);

}  // namespace vkpath::test

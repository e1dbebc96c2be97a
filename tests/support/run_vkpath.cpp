#include "support/run_vkpath.h"

#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>

namespace vkpath::test {
namespace {

std::string slurp(const std::filesystem::path& path) {
    std::ifstream in(path);
    std::stringstream s;
    s << in.rdbuf();
    return s.str();
}

}  // namespace

CommandResult runVkpath(const std::string& args, int timeoutSeconds) {
    static int counter = 0;
    const auto dir = std::filesystem::temp_directory_path() /
                     ("vkpath-run-" + std::to_string(getpid()) + "-" + std::to_string(counter++));
    std::filesystem::create_directories(dir);
    const auto out = dir / "out", err = dir / "err";
    const std::string limit =
        timeoutSeconds > 0 ? "timeout -k 5 " + std::to_string(timeoutSeconds) + " " : std::string();
    const std::string command = limit + "'" + VKPATH_BINARY + "' " + args + " >'" + out.string() +
                                "' 2>'" + err.string() + "' </dev/null";
    const int status = std::system(command.c_str());
    CommandResult result;
    result.exitCode = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
    // timeout's own codes: 124 after its SIGTERM, 137 after its SIGKILL.
    result.timedOut = timeoutSeconds > 0 && (result.exitCode == 124 || result.exitCode == 137);
    result.out = slurp(out);
    result.err = slurp(err);
    std::filesystem::remove_all(dir);
    return result;
}

RunningVkpath::RunningVkpath(const std::string& args) {
    static int counter = 0;
    m_dir = (std::filesystem::temp_directory_path() /
             ("vkpath-bg-" + std::to_string(getpid()) + "-" + std::to_string(counter++)))
                .string();
    std::filesystem::create_directories(m_dir);
    // exec: the shell becomes vkpath, so the pid is vkpath's.
    const std::string command = std::string("exec '") + VKPATH_BINARY + "' " + args + " >'" +
                                m_dir + "/out' 2>'" + m_dir + "/err' </dev/null";
    m_pid = fork();
    if (m_pid < 0) throw std::runtime_error("fork failed");
    if (m_pid == 0) {
        execl("/bin/sh", "sh", "-c", command.c_str(), static_cast<char*>(nullptr));
        _exit(127);
    }
}

RunningVkpath::~RunningVkpath() {
    if (m_pid > 0) {
        kill(m_pid, SIGKILL);
        waitpid(m_pid, nullptr, 0);
    }
    std::filesystem::remove_all(m_dir);
}

void RunningVkpath::signal(int signal) const {
    kill(m_pid, signal);
}

std::string RunningVkpath::err() const {
    return slurp(m_dir + "/err");
}

CommandResult RunningVkpath::wait() {
    int status = 0;
    waitpid(m_pid, &status, 0);
    m_pid = -1;
    CommandResult result;
    result.exitCode = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
    result.out = slurp(m_dir + "/out");
    result.err = slurp(m_dir + "/err");
    return result;
}

int lineCount(const std::string& text) {
    int lines = 0;
    for (char c : text) lines += c == '\n';
    if (!text.empty() && text.back() != '\n') ++lines;
    return lines;
}

}  // namespace vkpath::test

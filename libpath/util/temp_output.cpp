#include "util/temp_output.h"

#include <fcntl.h>
#include <signal.h>
#include <sys/file.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <utility>

#include "util/error.h"

namespace lt {

std::string temporaryName(const std::string& finalPath) { return finalPath + ".partial-" + std::to_string(::getpid()); }

void removeStaleTemporaries(const std::string& finalPath) {
    namespace fs = std::filesystem;
    const fs::path final(finalPath);
    const std::string prefix = final.filename().string() + ".partial-";
    const fs::path dir = final.has_parent_path() ? final.parent_path() : fs::path(".");
    std::error_code ec;
    for (fs::directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec)) {
        const std::string name = it->path().filename().string();
        if (name.size() <= prefix.size() || name.compare(0, prefix.size(), prefix) != 0) continue;
        const std::string pid = name.substr(prefix.size());
        if (pid.size() > 9 || pid.find_first_not_of("0123456789") != std::string::npos) continue;
        const long id = std::stol(pid);
        // kill(pid, 0) probes without sending: ESRCH is a process that no longer exists.
        if (!(id > 0) || id == long(::getpid()) || ::kill(pid_t(id), 0) == 0 || errno != ESRCH) continue;
        const int fd = ::open(it->path().c_str(), O_RDONLY | O_CLOEXEC);
        if (fd < 0) continue;
        if (::flock(fd, LOCK_EX | LOCK_NB) == 0) {
            std::error_code ignored;
            fs::remove(it->path(), ignored);
        }
        ::close(fd);
    }
}

void lockAsWriting(int fd) { (void)::flock(fd, LOCK_EX | LOCK_NB); }

TempOutput::TempOutput(std::string finalPath) : final_(std::move(finalPath)), temp_(temporaryName(final_)) {
    removeStaleTemporaries(final_);
    lock_ = ::open(temp_.c_str(), O_WRONLY | O_CREAT | O_CLOEXEC, 0666);
    if (lock_ >= 0) lockAsWriting(lock_);
}

TempOutput::~TempOutput() {
    if (!committed_) ::unlink(temp_.c_str());
    if (lock_ >= 0) ::close(lock_);
}

void TempOutput::commit() {
    // fsync before the rename: otherwise a crash can leave the final name pointing at an empty file.
    const int fd = ::open(temp_.c_str(), O_RDONLY | O_CLOEXEC);
    if (fd < 0) throw Error(final_ + ": cannot open temporary file " + temp_ + " (" + std::strerror(errno) + ")");
    const bool synced = ::fsync(fd) == 0;
    const int syncErr = errno;
    ::close(fd);
    if (!synced) throw Error(final_ + ": cannot sync to disk (" + std::strerror(syncErr) + ")");
    if (::rename(temp_.c_str(), final_.c_str()) != 0)
        throw Error(final_ + ": cannot rename " + temp_ + " to it (" + std::strerror(errno) + ")");
    committed_ = true;
}

} // namespace lt

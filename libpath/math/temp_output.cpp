#include "math/temp_output.h"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <utility>

#include "math/error.h"

namespace lt {

TempOutput::TempOutput(std::string finalPath)
    : final_(std::move(finalPath)), temp_(final_ + ".partial-" + std::to_string(::getpid())) {}

TempOutput::~TempOutput() {
    if (!committed_) ::unlink(temp_.c_str());
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

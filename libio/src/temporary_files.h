// Temporary outputs: where they live, the registry that removes them on a signal, and the
// removal of those a killed process left behind.
#pragma once

#include <filesystem>
#include <string>
#include <sys/types.h>

namespace dhdr::detail {

// Adds and removes the temporaries that the process has open; see removeTemporaryOutputsOnSignals.
void registerTemporary(const std::string& path);
void unregisterTemporary(const std::string& path);
void installTemporaryHandlers();

// ".NAME.tmpPID.EXT": where a temporary of `target` written by process `pid` lives.
std::filesystem::path temporaryFor(const std::filesystem::path& target, pid_t pid);

// Removes temporaries of `target` whose writer is gone (killed by SIGKILL, or a crash the
// handlers could not see); a live process's are left alone.
void removeStaleTemporaries(const std::filesystem::path& target);

} // namespace dhdr::detail

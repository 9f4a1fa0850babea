#pragma once
/// \file Output files appear whole or not at all: write to a temporary beside the target, then
/// rename (rename(2) is atomic within a file system).
#include <filesystem>
#include <functional>
#include <iosfwd>
#include <string>
#include <vector>

namespace shvol {

/// Calls write(tmpPath), then renames tmpPath to path. If write throws, the temporary is removed
/// and the exception propagates; the target is never left half-written. A path that is a
/// symbolic link writes its target (the link stays); a directory, device, FIFO or socket
/// there throws before write is called ("path: cannot write: is not a regular file (…)"). A
/// SIGTERM, SIGHUP or SIGINT that ends the process meanwhile (one whose action was the default when
/// the first write began) removes the temporary too before the process ends as the signal would
/// have ended it.
void writeAtomically(const std::string& path, const std::function<void(const std::string&)>& write);

/// Removes from `directory` the temporaries that processes no longer running left, regular files
/// `NAME.tmpPID` whose NAME is `ours` and whose PID runs nothing (ESRCH): SIGKILL (`kill -9`,
/// mpirun's a second after it passed a Ctrl-C on) and power cuts end a process before it removes
/// its own, and a checkpoint's is as large as the checkpoint (helper 147). For directories and
/// names the caller owns (a batch's output directory, under its lock; a render's checkpoint): a
/// PID of another PID namespace or host reads as not running, and any file so named goes.
void removeStaleTemporaries(const std::string& directory,
                            const std::function<bool(const std::string&)>& ours);

/// One file of writeTogether: where it goes and what writes it (given its temporary's path).
struct FileWrite {
    std::string path;
    std::function<void(const std::string&)> write;
};

/// Writes files that belong together (an image and its statistics) as writeAtomically does each,
/// all into their temporaries first and then renamed in order, and a signal that would end the
/// process during the renames ends it after the last: a failure or a signal while they are
/// written leaves none of them, and one at their renames all of them. (Only a rename that itself
/// fails, or a power cut, leaves the ones before it: the error names them. Groups written at once
/// on several threads, batch --jobs: a signal deferred by one group's renames lets another group
/// that reaches its renames meanwhile finish them, whole.) afterRename(i), when given, is called
/// after the i-th rename (a test's signal comes there).
void writeTogether(const std::vector<FileWrite>& files,
                   const std::function<void(size_t)>& afterRename = {});

/// Installs, once, the handlers behind that promise: for SIGTERM, SIGHUP and SIGINT whose action
/// is still the default (not one the shell ignores, as nohup does SIGHUP), a handler that
/// unlinks the temporaries being written and then ends the process as the signal would have.
/// writeAtomically calls it; a program installing handlers of its own (InterruptGuard) calls it
/// first and hands signals back to what it replaced.
void removeTemporariesOnSignals();

/// What `path` names once its symbolic links are followed: itself if it is no link, else the
/// last link's target (relative targets taken from their link's directory), which need not
/// exist. Forty links at most, as the kernel allows: a loop stays a link, which
/// outputFileProblem and writeAtomically refuse.
std::filesystem::path linkTarget(const std::string& path);

/// Why a file cannot be written at path, as far as can be told before writing it: "directory D
/// does not exist", "A is not a directory" (D, or an ancestor A of it, is a file), "directory D
/// is not writable (reason)" (by its permissions, or because a file made there to find out
/// could not be), "is a directory", "is not a regular file (…)" (a device, FIFO or
/// socket, which the rename of writeAtomically would replace) or "cannot be resolved (…)" (a
/// loop of links); empty otherwise. Symbolic links
/// are followed: what counts is the file their target names. A command checks its outputs
/// with it before the work that fills them.
std::string outputFileProblem(const std::string& path);
/// Why the directory at path cannot be made (with its parents) and written into: its nearest
/// existing ancestor, or itself ("it"), "is not a directory" or is not writable; empty otherwise.
std::string outputDirectoryProblem(const std::string& path);

/// Throws shvol::Error "path: cannot write file (reason)", the reason being the message of errno
/// value `error` (the errno a failed open, write or rename left; 0: no reason known).
[[noreturn]] void failWriting(const std::string& path, int error);

/// Writes the temporary `tmp` of `path` (writeAtomically's, writeTogether's) through write(os),
/// os a binary stream on it, checked once it is closed: a write that failed, also in a library's
/// destructor or the stream's last flush, is failWriting(path, its reason); an exception write
/// throws is "path: cannot write FORMAT (its message)", or failWriting where the stream failed.
/// (A library writing its own stream never checked it: a full disk left a truncated EXR or VDB
/// renamed into place and reported written; helper 100.)
void writeStreamTo(const std::string& tmp, const std::string& path, const std::string& format,
                   const std::function<void(std::ofstream&)>& write);

/// Writes text (any bytes) to path atomically.
void writeTextAtomically(const std::string& path, const std::string& text);

}  // namespace shvol

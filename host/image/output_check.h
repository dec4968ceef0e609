// The one check every command runs on its outputs before any rendering: each output can
// be written (its kind and directory), and no output is an input or another output of the
// same run, compared by the file they resolve to, however they are spelled.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

namespace penumbra {

// A file a run reads or writes, with what it is for messages: `role` such as "-o", "--png",
// "the scene", "jobs[2].output".
struct RunFile {
    std::filesystem::path path;
    std::string role;
};

// What identifies the file `path` names: "inode DEV:INO" when it exists (so hard links and
// symlinks compare equal), else its absolute path with symlinks of the existing prefix
// resolved and "." and ".." removed (so "./a", "a", "/abs/a" and "link/a" compare equal).
std::string fileIdentity(const std::filesystem::path& path);

// Throws InputError (exit 2) when an output is the same file as an input or as another
// output: `prefix` + "ROLE \"PATH\" is the same file as ROLE \"PATH\"; ...". Every output
// must differ, except that several may go to one character device (/dev/null); inputs may
// repeat.
void checkDistinctFiles(const std::vector<RunFile>& outputs, const std::vector<RunFile>& inputs,
                        const std::string& prefix = "");

// Throws std::runtime_error("cannot write PATH: why") (exit 1) when `output` cannot be
// written: a directory, a block device or socket, a device or FIFO without write
// permission, a missing or unwritable directory, a symlink loop. A symlink is judged by
// the file it leads to. With `createDirectory` the directory is created first (batch).
void checkWritable(const std::filesystem::path& output, bool createDirectory = false);

// Both checks, the clobbering one first (bad usage outranks a runtime failure).
void checkOutputs(const std::vector<RunFile>& outputs, const std::vector<RunFile>& inputs,
                  bool createDirectories = false);

}  // namespace penumbra

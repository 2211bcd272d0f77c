#include "glintscope/core/atomic_output.hpp"

#include <algorithm>
#include <atomic>
#include <cctype>
#include <csignal>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <system_error>

#include <fcntl.h>
#include <sys/syscall.h>
#include <unistd.h>

#include "glintscope/core/error.hpp"
#include "glintscope/core/text_format.hpp"

namespace glintscope {
namespace {

// ---- Temporaries removed on SIGINT, SIGTERM and SIGHUP --------------------------------------
//
// Each output is written inside its own temporary directory beside the target, so whatever a
// writer creates there (libzip writes its own "<name>.XXXXXX" before renaming) goes with it.
// The live directories sit in fixed slots that a signal handler reads without locks or
// allocation; it empties and removes them with async-signal-safe calls only (open, getdents64,
// unlinkat, rmdir), restores the default action and re-raises, so the process still ends with
// the signal's status.

constexpr int kSlots = 64;               // outputs written at once (one per thread at most)
constexpr std::size_t kPathBytes = 4096;

struct TemporarySlot {
    std::atomic<int> state{0};  // 0 free, 1 being set, 2 holds a live temporary directory
    char path[kPathBytes] = {};
};
TemporarySlot slots[kSlots];
constexpr int kSignals[] = {SIGINT, SIGTERM, SIGHUP};

// Removes a directory holding only files; async-signal-safe.
void remove_flat_directory(const char* path) {
    const int fd = ::open(path, O_RDONLY | O_DIRECTORY | O_CLOEXEC);
    if (fd >= 0) {
        alignas(8) char entries[4096];
        for (;;) {
            const long bytes = ::syscall(SYS_getdents64, fd, entries, sizeof entries);
            if (bytes <= 0) break;
            for (long offset = 0; offset < bytes;) {
                // linux_dirent64: d_ino (8), d_off (8), d_reclen (2), d_type (1), d_name.
                unsigned short record = 0;
                std::memcpy(&record, entries + offset + 16, sizeof record);
                const char* name = entries + offset + 19;
                if (std::strcmp(name, ".") != 0 && std::strcmp(name, "..") != 0) ::unlinkat(fd, name, 0);
                offset += record;
            }
        }
        ::close(fd);
    }
    ::rmdir(path);
}

extern "C" void remove_temporaries_and_reraise(int signal_number) {
    for (TemporarySlot& slot : slots)
        if (slot.state.load() == 2) remove_flat_directory(slot.path);
    std::signal(signal_number, SIG_DFL);
    std::raise(signal_number);
}

// Installed once, and only over the default action: a program's own handlers, or a signal
// ignored on purpose (nohup, background jobs of a script), are left alone.
void install_signal_handlers() {
    static const bool installed = [] {
        for (int signal_number : kSignals) {
            struct sigaction current {};
            if (::sigaction(signal_number, nullptr, &current) != 0 || current.sa_handler != SIG_DFL) continue;
            struct sigaction action {};
            action.sa_handler = remove_temporaries_and_reraise;
            sigemptyset(&action.sa_mask);
            ::sigaction(signal_number, &action, nullptr);
        }
        return true;
    }();
    (void)installed;
}

// Registers a temporary directory with the handler for its lifetime. A path too long for a
// slot, or a 65th concurrent output, is not tracked (it is still removed on exceptions).
class TrackedTemporary {
public:
    explicit TrackedTemporary(const std::string& path) {
        install_signal_handlers();
        if (path.size() >= kPathBytes) return;
        for (TemporarySlot& slot : slots) {
            int expected = 0;
            if (!slot.state.compare_exchange_strong(expected, 1)) continue;
            std::memcpy(slot.path, path.c_str(), path.size() + 1);
            slot.state.store(2);
            slot_ = &slot;
            return;
        }
    }
    ~TrackedTemporary() {
        if (slot_) slot_->state.store(0);
    }
    TrackedTemporary(const TrackedTemporary&) = delete;
    TrackedTemporary& operator=(const TrackedTemporary&) = delete;

private:
    TemporarySlot* slot_ = nullptr;
};

}  // namespace

std::string file_extension(const std::string& path) {
    std::string ext = std::filesystem::path(path).extension().string();
    if (!ext.empty() && ext.front() == '.') ext.erase(0, 1);
    std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char ch) { return std::tolower(ch); });
    return ext;
}

void write_text_file(const std::string& path, const std::string& text) {
    write_atomically(path, [&](const std::string& temporary) {
        std::ofstream stream(temporary, std::ios::binary);
        stream << text;
        stream.close();
        if (!stream) throw Error("cannot write '" + path + "'");
    });
}

void check_output_path(const std::string& path, const std::vector<std::string>& extensions, const std::string& what) {
    namespace fs = std::filesystem;
    if (path.empty()) throw Error(what + ": no output file name given");
    const std::string extension = file_extension(path);
    if (std::find(extensions.begin(), extensions.end(), extension) == extensions.end())
        throw Error(what + " '" + path + "': the file name must end in ." + join(extensions, " or ."));
    const fs::path target(path);
    const fs::path directory = target.has_parent_path() ? target.parent_path() : fs::path(".");
    std::error_code ec;
    if (!fs::is_directory(directory, ec))
        throw Error(what + " '" + path + "': directory '" + directory.string() + "' does not exist");
    if (fs::is_directory(target, ec)) throw Error(what + " '" + path + "': it is a directory");
    if (::access(directory.c_str(), W_OK) != 0)
        throw Error(what + " '" + path + "': directory '" + directory.string() + "' is not writable");
}

void write_atomically(const std::string& path, const std::function<void(const std::string&)>& write) {
    namespace fs = std::filesystem;
    if (path.empty()) throw Error("no output file name given");
    const fs::path target(path);
    const fs::path directory = target.has_parent_path() ? target.parent_path() : fs::path(".");
    std::error_code ec;
    if (!fs::is_directory(directory, ec))
        throw Error("cannot write '" + path + "': directory '" + directory.string() + "' does not exist");
    if (fs::is_directory(target, ec)) throw Error("cannot write '" + path + "': it is a directory");
    static std::atomic<unsigned> counter{0};
    // The temporary keeps the target's name (OpenImageIO picks the format from its extension)
    // inside a private directory on the same file system, so the final rename is atomic.
    const fs::path scratch = directory / (".glintscope-" + std::to_string(::getpid()) + "-" +
                                          std::to_string(counter++) + ".partial");
    if (!fs::create_directory(scratch, ec))
        throw Error("cannot write '" + path + "': cannot create a temporary in '" + directory.string() + "'");
    const TrackedTemporary tracked(scratch.string());
    const fs::path temporary = scratch / target.filename();
    try {
        write(temporary.string());
        fs::rename(temporary, target);
        fs::remove_all(scratch, ec);
    } catch (const fs::filesystem_error& e) {
        fs::remove_all(scratch, ec);
        throw Error("cannot write '" + path + "': " + e.code().message());
    } catch (...) {
        fs::remove_all(scratch, ec);
        throw;
    }
}

}  // namespace glintscope

#include "glintscope/atomic_output.hpp"

#include <algorithm>
#include <atomic>
#include <cctype>
#include <filesystem>
#include <fstream>
#include <system_error>
#include <unistd.h>

#include "glintscope/error.hpp"
#include "glintscope/text_format.hpp"

namespace glintscope {

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
    // The temporary keeps the target's extension: OpenImageIO picks the format from it.
    const fs::path temporary = directory / (".glintscope-" + std::to_string(::getpid()) + "-" +
                                            std::to_string(counter++) + "-" + target.filename().string());
    try {
        write(temporary.string());
        fs::rename(temporary, target);
    } catch (const fs::filesystem_error& e) {
        fs::remove(temporary, ec);
        throw Error("cannot write '" + path + "': " + e.code().message());
    } catch (...) {
        fs::remove(temporary, ec);
        throw;
    }
}

}  // namespace glintscope

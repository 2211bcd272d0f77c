#include "zip_files.hpp"

#include <zip.h>

namespace glintscope::testing {

bool write_zip(const std::string& path, const std::vector<std::pair<std::string, std::string>>& members) {
    int code = 0;
    zip_t* archive = zip_open(path.c_str(), ZIP_CREATE | ZIP_TRUNCATE, &code);
    if (!archive) return false;
    for (const auto& [name, contents] : members) {
        zip_source_t* source = zip_source_buffer(archive, contents.data(), contents.size(), 0);
        if (!source || zip_file_add(archive, name.c_str(), source, ZIP_FL_OVERWRITE) < 0) {
            zip_discard(archive);
            return false;
        }
    }
    return zip_close(archive) == 0;
}

std::string read_zip_member(const std::string& path, const std::string& name) {
    int code = 0;
    zip_t* archive = zip_open(path.c_str(), ZIP_RDONLY, &code);
    if (!archive) return {};
    zip_stat_t stat;
    std::string contents;
    if (zip_stat(archive, name.c_str(), 0, &stat) == 0) {
        contents.resize(stat.size);
        zip_file_t* file = zip_fopen(archive, name.c_str(), 0);
        if (file) {
            zip_fread(file, contents.data(), stat.size);
            zip_fclose(file);
        }
    }
    zip_discard(archive);
    return contents;
}

}  // namespace glintscope::testing

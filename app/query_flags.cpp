#include "query_flags.hpp"

#include <algorithm>
#include <map>

#include "glintscope/core/error.hpp"
#include "glintscope/pipeline/pipeline.hpp"
#include "glintscope/lobe/query.hpp"
#include "glintscope/core/text_format.hpp"

namespace glintscope::cli {

std::string flag_name(const std::string& key) {
    std::string name = "--" + key;
    std::replace(name.begin(), name.end(), '_', '-');
    return name;
}

void add_query_flags(CLI::App& command, QueryText& given, Quantity, const std::vector<std::string>& skip) {
    for (const QueryKey& key : query_keys()) {
        if (key.name == "heightfield" || std::find(skip.begin(), skip.end(), key.name) != skip.end()) continue;
        auto* option = command.add_option_function<std::string>(
            flag_name(key.name), [&given, name = key.name](const std::string& value) { given.emplace_back(name, value); },
            key.help);
        option->type_name(key.value_name);
        if (!key.implicit.empty()) option->expected(0, 1)->default_str(key.implicit);
    }
}

void add_method_option_flags(CLI::App& command, QueryText& given, Quantity quantity,
                             const std::vector<std::string>& only) {
    std::map<std::string, std::vector<std::string>> readers;
    std::map<std::string, std::string> helps;
    for (const MethodInfo& method : lobe_methods()) {
        if (!method.answers(quantity)) continue;
        if (!only.empty() && std::find(only.begin(), only.end(), method.name) == only.end()) continue;
        for (const MethodOption& option : method.options) {
            readers[option.key].push_back(method.name);
            helps[option.key] = option.help;
        }
    }
    for (const auto& [key, methods] : readers)
        command
            .add_option_function<std::string>(
                flag_name(key), [&given, key](const std::string& value) { given.emplace_back("option." + key, value); },
                join(methods) + ": " + helps[key])
            ->type_name("VALUE");
    command
        .add_option_function<std::vector<std::string>>(
            "--option",
            [&given](const std::vector<std::string>& options) {
                for (const std::string& option : options) {
                    const auto equals = option.find('=');
                    if (equals == std::string::npos || equals == 0)
                        throw CLI::ValidationError("--option", "'" + option + "' is not of the form KEY=VALUE");
                    given.emplace_back("option." + option.substr(0, equals), option.substr(equals + 1));
                }
            },
            "Method option KEY=VALUE (repeatable)")
        ->type_name("KEY=VALUE");
}

}  // namespace glintscope::cli

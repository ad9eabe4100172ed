// SPDX-License-Identifier: Apache-2.0
#include "vdbmap/plugin/PluginLoader.h"

#include <dlfcn.h>

#include <algorithm>
#include <cstdlib>
#include <map>
#include <memory>
#include <mutex>
#include <set>

#include "plugin/PluginRegistry.h"
#include "vdbmap/Error.h"
#include "vdbmap/pipeline/StageRegistry.h"

namespace vdbmap {
namespace fs = std::filesystem;

namespace {

constexpr const char* kPrefix = "vdbmap_plugin_";
constexpr const char* kSuffix = ".so";

struct LoaderState {
    std::mutex mutex;
    std::vector<fs::path> extra_dirs;
    std::map<fs::path, void*> handles;  // canonical path -> dlopen handle, never closed
};

LoaderState& state() {
    static LoaderState* s = new LoaderState();  // never destroyed, like the registry
    return *s;
}

std::string dlError() {
    const char* e = ::dlerror();
    return e != nullptr ? std::string(e) : std::string("no error text");
}

bool isPathSpec(const std::string& spec) {
    return spec.find('/') != std::string::npos ||
           (spec.size() > 3 && spec.compare(spec.size() - 3, 3, kSuffix) == 0);
}

std::string str(std::uint32_t v) { return std::to_string(v); }

struct PendingStage {
    std::string name;
    std::string summary;
    detail::PluginStageFactory factory;
};

/// Calls the plugin's register_stages and checks the stages it declares, without touching
/// the registry. Throws PluginError.
std::vector<PendingStage> collectStages(const fs::path& file, const vdbmap_plugin_info& info,
                                        const std::string& plugin_name) {
    vdbmap_registry reg;
    reg.origin = file.string();
    const int rc = info.register_stages(&reg);
    if (rc != 0) {
        throw PluginError(file.string() + ": plugin '" + plugin_name +
                          "' failed to register its stages: expected return code 0, found " +
                          std::to_string(rc) + (reg.error.empty() ? "" : " (" + reg.error + ")"));
    }
    std::vector<PendingStage> pending;
    std::set<std::string> names;
    for (auto factory : reg.factories) {
        std::unique_ptr<Stage> probe;
        try {
            probe.reset(factory());
        } catch (const std::exception& e) {
            throw PluginError(file.string() + ": a stage constructor of plugin '" + plugin_name +
                              "' threw: " + e.what());
        }
        if (!probe) {
            throw PluginError(file.string() + ": a stage factory of plugin '" + plugin_name +
                              "' returned null");
        }
        PendingStage stage{std::string(probe->name()), std::string(probe->summary()), factory};
        if (stage.name.empty()) {
            throw PluginError(file.string() + ": plugin '" + plugin_name +
                              "' registers a stage with an empty name");
        }
        if (!names.insert(stage.name).second || StageRegistry::instance().contains(stage.name)) {
            throw PluginError(file.string() + ": plugin '" + plugin_name + "' registers stage '" +
                              stage.name + "', but that name is already registered");
        }
        pending.push_back(std::move(stage));
    }
    return pending;
}

}  // namespace

std::vector<fs::path> PluginLoader::searchPath() {
    std::vector<fs::path> dirs;
    if (const char* env = std::getenv("VDBMAP_PLUGIN_PATH")) {
        std::string list(env);
        std::size_t start = 0;
        while (start <= list.size()) {
            std::size_t end = list.find(':', start);
            if (end == std::string::npos) end = list.size();
            if (end > start) dirs.emplace_back(list.substr(start, end - start));
            start = end + 1;
        }
    }
    {
        std::lock_guard<std::mutex> lock(state().mutex);
        dirs.insert(dirs.end(), state().extra_dirs.begin(), state().extra_dirs.end());
    }
#ifdef VDBMAP_BUILD_PLUGIN_DIR
    dirs.emplace_back(VDBMAP_BUILD_PLUGIN_DIR);
#endif
#ifdef VDBMAP_INSTALL_PLUGIN_DIR
    dirs.emplace_back(VDBMAP_INSTALL_PLUGIN_DIR);
#endif
    std::vector<fs::path> unique;
    for (auto& dir : dirs) {
        fs::path normal = dir.lexically_normal();
        if (std::find(unique.begin(), unique.end(), normal) == unique.end()) {
            unique.push_back(normal);
        }
    }
    return unique;
}

void PluginLoader::addSearchDirectory(const fs::path& dir) {
    std::lock_guard<std::mutex> lock(state().mutex);
    fs::path normal = dir.lexically_normal();
    auto& dirs = state().extra_dirs;
    if (std::find(dirs.begin(), dirs.end(), normal) == dirs.end()) dirs.push_back(normal);
}

fs::path PluginLoader::resolve(const std::string& spec, const fs::path& base_dir) {
    if (spec.empty()) throw PluginError("plugin: empty plugin name");
    std::error_code ec;
    if (isPathSpec(spec)) {
        fs::path file(spec);
        if (file.is_relative() && !base_dir.empty()) file = base_dir / file;
        if (!fs::is_regular_file(file, ec)) {
            throw PluginError(file.string() + ": plugin file not found (expected a file " +
                              kPrefix + "<name>" + kSuffix + ")");
        }
        fs::path canonical = fs::canonical(file, ec);
        return ec ? file : canonical;
    }
    const std::string file_name = kPrefix + spec + kSuffix;
    std::string looked;
    for (const auto& dir : searchPath()) {
        fs::path file = dir / file_name;
        if (fs::is_regular_file(file, ec)) {
            fs::path canonical = fs::canonical(file, ec);
            return ec ? file : canonical;
        }
        looked += "\n  " + dir.string();
    }
    throw PluginError("plugin '" + spec + "' not found: expected " + file_name +
                      " in one of (set VDBMAP_PLUGIN_PATH or give a path):" + looked);
}

fs::path PluginLoader::load(const std::string& spec, const fs::path& base_dir) {
    const fs::path file = resolve(spec, base_dir);
    std::lock_guard<std::mutex> lock(state().mutex);
    if (state().handles.count(file) > 0) return file;

    ::dlerror();
    void* handle = ::dlopen(file.c_str(), RTLD_NOW | RTLD_LOCAL);
    if (handle == nullptr) {
        throw PluginError(file.string() +
                          ": cannot load plugin: expected a shared object built against "
                          "libvdbmap, found: " + dlError());
    }
    // Closes the handle on every failure before the plugin could register anything.
    std::unique_ptr<void, int (*)(void*)> guard(handle, &::dlclose);

    ::dlerror();
    void* symbol = ::dlsym(handle, VDBMAP_PLUGIN_ENTRY_SYMBOL);
    if (symbol == nullptr) {
        throw PluginError(file.string() + ": not a vdbmap plugin: expected the entry symbol '" +
                          VDBMAP_PLUGIN_ENTRY_SYMBOL + "', found none (" + dlError() + ")");
    }
    using EntryFn = const vdbmap_plugin_info* (*)();
    const vdbmap_plugin_info* info = reinterpret_cast<EntryFn>(symbol)();
    if (info == nullptr) {
        throw PluginError(file.string() + ": " + VDBMAP_PLUGIN_ENTRY_SYMBOL +
                          "() returned null: expected a plugin description");
    }
    // Only the leading fields are read before the ABI check: their layout never changes.
    if (info->abi_version != VDBMAP_PLUGIN_ABI_VERSION) {
        throw PluginError(file.string() + ": plugin ABI mismatch: expected vdbmap plugin ABI " +
                          str(VDBMAP_PLUGIN_ABI_VERSION) + ", found " + str(info->abi_version) +
                          "; rebuild the plugin against vdbmap " + VDBMAP_VERSION_STRING);
    }
    if (info->openvdb_abi != OPENVDB_ABI_VERSION_NUMBER) {
        throw PluginError(file.string() + ": OpenVDB ABI mismatch: expected OpenVDB ABI " +
                          str(OPENVDB_ABI_VERSION_NUMBER) + ", found " + str(info->openvdb_abi));
    }
    const std::string plugin_name = info->name != nullptr ? info->name : "";
    if (info->register_stages == nullptr) {
        throw PluginError(file.string() + ": plugin '" + plugin_name +
                          "' has no register_stages function: expected one, found null");
    }
    std::vector<PendingStage> stages = collectStages(file, *info, plugin_name);
    for (auto& stage : stages) {
        auto factory = stage.factory;
        StageRegistry::instance().add(
            stage.name, stage.summary, [factory] { return std::unique_ptr<Stage>(factory()); },
            file.string());
    }
    guard.release();
    state().handles.emplace(file, handle);
    return file;
}

std::vector<std::string> PluginLoader::discover() {
    std::set<std::string> names;
    std::error_code ec;
    for (const auto& dir : searchPath()) {
        if (!fs::is_directory(dir, ec)) continue;
        for (fs::directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec)) {
            const std::string file = it->path().filename().string();
            const std::size_t prefix = std::string(kPrefix).size();
            if (file.size() > prefix + 3 && file.rfind(kPrefix, 0) == 0 &&
                file.compare(file.size() - 3, 3, kSuffix) == 0) {
                names.insert(file.substr(prefix, file.size() - prefix - 3));
            }
        }
    }
    return {names.begin(), names.end()};
}

std::vector<fs::path> PluginLoader::loaded() {
    std::lock_guard<std::mutex> lock(state().mutex);
    std::vector<fs::path> out;
    for (const auto& [path, handle] : state().handles) out.push_back(path);
    return out;
}

}  // namespace vdbmap

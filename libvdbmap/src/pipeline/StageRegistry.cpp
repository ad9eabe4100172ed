// SPDX-License-Identifier: Apache-2.0
#include "vdbmap/pipeline/StageRegistry.h"

#include <algorithm>
#include <map>
#include <mutex>

#include "vdbmap/Error.h"

namespace vdbmap {

struct StageRegistry::Impl {
    mutable std::mutex mutex;
    std::map<std::string, Entry> entries;
};

StageRegistry::StageRegistry() : impl_(std::make_unique<Impl>()) {}

StageRegistry& StageRegistry::instance() {
    // Never destroyed: plugin stages may still be alive during static destruction.
    static StageRegistry* registry = new StageRegistry();
    return *registry;
}

void StageRegistry::add(const std::string& name, const std::string& summary,
                        StageFactory factory, const std::string& origin) {
    if (name.empty()) throw InvalidInput("StageRegistry: a stage from " + origin + " has an empty name");
    if (!factory) throw InvalidInput("StageRegistry: stage '" + name + "' has no factory");
    std::lock_guard<std::mutex> lock(impl_->mutex);
    auto it = impl_->entries.find(name);
    if (it != impl_->entries.end()) {
        throw InvalidInput("StageRegistry: stage '" + name + "' from " + origin +
                           " is already registered by " + it->second.origin);
    }
    impl_->entries.emplace(name, Entry{name, summary, origin, std::move(factory)});
}

bool StageRegistry::contains(const std::string& name) const {
    std::lock_guard<std::mutex> lock(impl_->mutex);
    return impl_->entries.count(name) > 0;
}

std::unique_ptr<Stage> StageRegistry::create(const std::string& name) const {
    StageFactory factory;
    {
        std::lock_guard<std::mutex> lock(impl_->mutex);
        auto it = impl_->entries.find(name);
        if (it == impl_->entries.end()) {
            std::string known;
            for (const auto& [key, entry] : impl_->entries) {
                known += (known.empty() ? "" : ", ") + key;
            }
            throw ConfigError("unknown stage '" + name + "'; registered stages: " +
                              (known.empty() ? std::string("(none)") : known) +
                              " (plugin stages need `plugins: [name]` in the config)");
        }
        factory = it->second.factory;
    }
    std::unique_ptr<Stage> stage = factory();
    if (!stage) throw Error("StageRegistry: the factory of stage '" + name + "' returned null");
    return stage;
}

std::vector<StageRegistry::Entry> StageRegistry::entries() const {
    std::lock_guard<std::mutex> lock(impl_->mutex);
    std::vector<Entry> out;
    out.reserve(impl_->entries.size());
    for (const auto& [name, entry] : impl_->entries) out.push_back(entry);
    return out;
}

}  // namespace vdbmap

#include "render/frame_graph.hpp"

#include <algorithm>
#include <chrono>

#include "core/error.hpp"

namespace candela {

TexturePool::TexturePool()
    : TexturePool([](const TextureDesc& d) {
          return d.samples > 1 ? gl::Texture::create_2d_multisample(d.format, d.width, d.height, d.samples)
                               : gl::Texture::create_2d(d.format, d.width, d.height, 1);
      }) {}

TexturePool::TexturePool(Factory factory) : factory_(std::move(factory)) {}

int TexturePool::acquire(const TextureDesc& desc) {
    for (size_t i = 0; i < slots_.size(); ++i)
        if (!slots_[i].used && slots_[i].desc == desc) {
            slots_[i].used = true;
            return static_cast<int>(i);
        }
    slots_.push_back({desc, factory_(desc), true});
    ++allocations_;
    return static_cast<int>(slots_.size()) - 1;
}

void TexturePool::release(int slot) { slots_.at(static_cast<size_t>(slot)).used = false; }

int TexturePool::in_use() const {
    return static_cast<int>(std::count_if(slots_.begin(), slots_.end(), [](const Slot& s) { return s.used; }));
}

void TexturePool::clear() { slots_.clear(); }

FrameGraph::ResourceId FrameGraph::Builder::create(const std::string& name, const TextureDesc& desc) {
    ResourceRecord r;
    r.name = name;
    r.desc = desc;
    r.creator = pass_;
    graph_.resources_.push_back(r);
    const ResourceId id = static_cast<ResourceId>(graph_.resources_.size()) - 1;
    graph_.passes_[static_cast<size_t>(pass_)].creates.push_back(id);
    graph_.passes_[static_cast<size_t>(pass_)].writes.push_back(id);
    return id;
}

FrameGraph::ResourceId FrameGraph::Builder::read(ResourceId id) {
    if (id < 0 || static_cast<size_t>(id) >= graph_.resources_.size())
        throw Error(ExitCode::internal, "frame graph: pass '" + graph_.passes_[static_cast<size_t>(pass_)].name +
                                            "' reads resource " + std::to_string(id) + ", which does not exist");
    graph_.passes_[static_cast<size_t>(pass_)].reads.push_back(id);
    return id;
}

FrameGraph::ResourceId FrameGraph::Builder::read(ResourceId id, unsigned unit) {
    read(id);
    auto& units = graph_.passes_[static_cast<size_t>(pass_)].units;
    for (const auto& [other, u] : units)
        if (u == unit)
            throw Error(ExitCode::internal, "frame graph: pass '" + graph_.passes_[static_cast<size_t>(pass_)].name +
                                                "' binds two resources to texture unit " + std::to_string(unit));
    units.emplace_back(id, unit);
    return id;
}

FrameGraph::ResourceId FrameGraph::Builder::write(ResourceId id) {
    if (id < 0 || static_cast<size_t>(id) >= graph_.resources_.size())
        throw Error(ExitCode::internal, "frame graph: pass '" + graph_.passes_[static_cast<size_t>(pass_)].name +
                                            "' writes resource " + std::to_string(id) + ", which does not exist");
    auto& pass = graph_.passes_[static_cast<size_t>(pass_)];
    pass.writes.push_back(id);
    // Drawing over what an earlier pass wrote depends on that pass.
    for (int p = 0; p < pass_; ++p) {
        const auto& w = graph_.passes_[static_cast<size_t>(p)].writes;
        if (std::find(w.begin(), w.end(), id) != w.end()) {
            pass.reads.push_back(id);
            break;
        }
    }
    return id;
}

void FrameGraph::Builder::side_effect() { graph_.passes_[static_cast<size_t>(pass_)].side_effect = true; }

const gl::Texture& FrameGraph::Context::texture(ResourceId id) const {
    const ResourceRecord& r = graph.resources_.at(static_cast<size_t>(id));
    if (r.imported) return *r.imported;
    return graph.pool_->texture(r.slot);
}

const TextureDesc& FrameGraph::Context::desc(ResourceId id) const { return graph.resources_.at(static_cast<size_t>(id)).desc; }

FrameGraph::ResourceId FrameGraph::import_texture(const std::string& name, const gl::Texture& texture,
                                                   const TextureDesc& desc) {
    ResourceRecord r;
    r.name = name;
    r.desc = desc;
    r.imported = &texture;
    resources_.push_back(r);
    return static_cast<ResourceId>(resources_.size()) - 1;
}

void FrameGraph::add_pass(const std::string& name, const Setup& setup, Execute execute) {
    PassRecord p;
    p.name = name;
    p.execute = std::move(execute);
    passes_.push_back(std::move(p));
    Builder b(*this, static_cast<int>(passes_.size()) - 1);
    setup(b);
}

void FrameGraph::mark_output(ResourceId id) { resources_.at(static_cast<size_t>(id)).output = true; }

void FrameGraph::compile(TexturePool& pool) {
    pool_ = &pool;
    // Every read must have an earlier writer (or be imported).
    for (size_t p = 0; p < passes_.size(); ++p)
        for (ResourceId id : passes_[p].reads) {
            const ResourceRecord& r = resources_.at(static_cast<size_t>(id));
            bool written = r.imported != nullptr;
            for (size_t q = 0; q < p && !written; ++q)
                written = std::find(passes_[q].writes.begin(), passes_[q].writes.end(), id) != passes_[q].writes.end();
            if (!written)
                throw Error(ExitCode::internal, "frame graph: pass '" + passes_[p].name + "' reads '" + r.name +
                                                    "' before any pass writes it");
        }
    // Cull backwards from the outputs.
    std::vector<bool> needed(resources_.size(), false);
    for (size_t i = 0; i < resources_.size(); ++i) needed[i] = resources_[i].output;
    for (size_t p = passes_.size(); p-- > 0;) {
        PassRecord& pass = passes_[p];
        bool live = pass.side_effect;
        for (ResourceId id : pass.writes) live = live || needed[static_cast<size_t>(id)];
        pass.culled = !live;
        if (!live) {
            pass.cull_reason = "nothing reads what it writes";
            continue;
        }
        for (ResourceId id : pass.reads) needed[static_cast<size_t>(id)] = true;
    }
    // Lifetimes over live passes, then slots in execution order.
    for (size_t p = 0; p < passes_.size(); ++p) {
        if (passes_[p].culled) continue;
        auto touch = [&](ResourceId id) {
            ResourceRecord& r = resources_[static_cast<size_t>(id)];
            if (r.first < 0) r.first = static_cast<int>(p);
            r.last = static_cast<int>(p);
        };
        for (ResourceId id : passes_[p].writes) touch(id);
        for (ResourceId id : passes_[p].reads) touch(id);
    }
    for (size_t p = 0; p < passes_.size(); ++p) {
        if (passes_[p].culled) continue;
        for (ResourceRecord& r : resources_)
            if (!r.imported && r.first == static_cast<int>(p)) r.slot = pool.acquire(r.desc);
        for (ResourceRecord& r : resources_)
            if (!r.imported && r.last == static_cast<int>(p) && !r.output) pool.release(r.slot);
    }
    compiled_ = true;
}

void FrameGraph::execute(gl::StateCache& state, const std::function<void(PassRecord&)>& before,
                         const std::function<void(PassRecord&)>& after) {
    if (!compiled_) throw Error(ExitCode::internal, "frame graph: execute() before compile()");
    for (PassRecord& pass : passes_) {
        if (pass.culled) continue;
        if (before) before(pass);
        const auto t0 = std::chrono::steady_clock::now();
        Context ctx{state, pass.counters, *this};
        for (const auto& [id, unit] : pass.units) gl::bind_texture_unit(unit, ctx.texture(id));
        pass.execute(ctx);
        for (const auto& [id, unit] : pass.units) glBindTextureUnit(unit, 0);
        pass.cpu_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
        if (after) after(pass);
    }
}

void FrameGraph::release(TexturePool& pool) {
    for (ResourceRecord& r : resources_)
        if (!r.imported && r.slot >= 0 && r.output) pool.release(r.slot);
}

std::vector<std::string> FrameGraph::live_pass_names() const {
    std::vector<std::string> names;
    for (const PassRecord& p : passes_)
        if (!p.culled) names.push_back(p.name);
    return names;
}

}  // namespace candela

#pragma once
// A frame graph (after Filament's and Frostbite's): passes declare the textures they create,
// read and write in a setup step and record GL work in an execute step. compile() culls every
// pass whose outputs reach no final output, gives each live transient texture a lifetime (first
// to last live use) and assigns it a pool slot; textures whose lifetimes do not overlap share a
// slot, and the pool keeps its textures across frames.
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include <glad/gl.h>

#include "gl/handles.hpp"
#include "gl/state.hpp"

namespace candela {

struct TextureDesc {
    GLenum format = GL_RGBA16F;
    int width = 0;
    int height = 0;
    int samples = 1;  // > 1: a multisampled texture (anti-aliasing's targets)
    bool operator==(const TextureDesc&) const = default;
};

// Textures by description. acquire() returns a free slot with an equal description, or creates
// one; release() makes it free again. Slots (and their GL textures) live across frames.
class TexturePool {
public:
    using Factory = std::function<gl::Texture(const TextureDesc&)>;
    TexturePool();  // creates GL textures (glTextureStorage2D, one level)
    explicit TexturePool(Factory factory);

    int acquire(const TextureDesc& desc);
    void release(int slot);
    const gl::Texture& texture(int slot) const { return slots_.at(static_cast<size_t>(slot)).texture; }
    const TextureDesc& desc(int slot) const { return slots_.at(static_cast<size_t>(slot)).desc; }
    int allocations() const { return allocations_; }  // textures created since construction
    int size() const { return static_cast<int>(slots_.size()); }
    int in_use() const;
    void clear();  // drops every texture (e.g. after a resize)

private:
    struct Slot {
        TextureDesc desc;
        gl::Texture texture;
        bool used = false;
    };
    Factory factory_;
    std::vector<Slot> slots_;
    int allocations_ = 0;
};

struct PassCounters {
    int draw_calls = 0;
    std::size_t triangles = 0;
    int dispatches = 0;
};

class FrameGraph {
public:
    using ResourceId = int;

    class Builder {
    public:
        // A transient texture this pass creates (and writes first).
        ResourceId create(const std::string& name, const TextureDesc& desc);
        ResourceId read(ResourceId id);
        // A texture the pass samples at texture unit `unit`: the graph binds it there before the
        // pass runs (with no sampler object: the texture's own filtering) and unbinds it after.
        ResourceId read(ResourceId id, unsigned unit);
        // Writing a resource another pass made also reads it (the pass draws over it).
        ResourceId write(ResourceId id);
        // The pass must run even if no output depends on it (e.g. a readback).
        void side_effect();

    private:
        friend class FrameGraph;
        Builder(FrameGraph& graph, int pass) : graph_(graph), pass_(pass) {}
        FrameGraph& graph_;
        int pass_;
    };

    struct Context {
        const gl::Texture& texture(ResourceId id) const;
        const TextureDesc& desc(ResourceId id) const;
        gl::StateCache& state;
        PassCounters& counters;
        const FrameGraph& graph;
    };

    using Setup = std::function<void(Builder&)>;
    using Execute = std::function<void(Context&)>;

    struct PassRecord {
        std::string name;
        std::vector<ResourceId> creates, reads, writes;
        std::vector<std::pair<ResourceId, unsigned>> units;  // reads bound to texture units (Builder::read)
        bool side_effect = false;
        bool culled = false;
        std::string cull_reason;
        PassCounters counters;
        double cpu_ms = 0.0;
        Execute execute;
    };

    struct ResourceRecord {
        std::string name;
        TextureDesc desc;
        const gl::Texture* imported = nullptr;  // not from the pool
        int creator = -1;
        bool output = false;
        // After compile(): the live lifetime [first, last] in pass indices and the pool slot.
        int first = -1, last = -1;
        int slot = -1;
    };

    ResourceId import_texture(const std::string& name, const gl::Texture& texture, const TextureDesc& desc);
    // Runs `setup` at once; `execute` runs in execute() if the pass survives culling.
    void add_pass(const std::string& name, const Setup& setup, Execute execute);
    // The same with the pass's own data (Filament's PassData): `setup` fills it (typically the
    // resource ids the pass reads and writes), `execute` reads it. The graph owns it; the returned
    // reference stays valid until the graph is destroyed.
    template <class Data>
    const Data& add_pass(const std::string& name, const std::function<void(Builder&, Data&)>& setup,
                         std::function<void(const Data&, Context&)> execute) {
        auto data = std::make_shared<Data>();
        add_pass(
            name, [&](Builder& b) { setup(b, *data); },
            [data, execute = std::move(execute)](Context& ctx) { execute(*data, ctx); });
        return *data;
    }
    void mark_output(ResourceId id);

    // Culls, computes lifetimes and assigns pool slots. Throws candela::Error (internal) when a pass
    // reads a resource no earlier pass wrote (passes are added in execution order).
    void compile(TexturePool& pool);
    // Runs the live passes in order; `before`/`after` bracket each (GPU timers, debug checks).
    void execute(gl::StateCache& state, const std::function<void(PassRecord&)>& before = {},
                 const std::function<void(PassRecord&)>& after = {});
    // Returns this frame's slots to the pool (compile() acquired them).
    void release(TexturePool& pool);

    const std::vector<PassRecord>& passes() const { return passes_; }
    const std::vector<ResourceRecord>& resources() const { return resources_; }
    std::vector<std::string> live_pass_names() const;

private:
    std::vector<PassRecord> passes_;
    std::vector<ResourceRecord> resources_;
    TexturePool* pool_ = nullptr;
    bool compiled_ = false;
};

}  // namespace candela

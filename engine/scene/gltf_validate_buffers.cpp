// glTF validation of buffers, bufferViews and accessors (spec 3.6).
#include "scene/gltf_validate_internal.hpp"

#include <algorithm>
#include <cmath>

namespace candela::gltf::validation {

void Validator::check_buffers() {
    buffer_len_.assign(count("buffers"), -1);
    for (auto [i, b] : items("buffers")) {
        const std::string p = at("buffers", i);
        const auto len = integer(*b, "byteLength", p, true, 1);
        if (len) buffer_len_[i] = *len;
        const std::string* uri = string(*b, "uri", p, false);
        if (uri) {
            if (auto data = parse_data_uri(*uri)) {
                size_t decoded = 0;
                if (data->media_type != "application/octet-stream" && data->media_type != "application/gltf-buffer")
                    problem(at(p, "uri"), "data URI media type must be application/octet-stream or application/gltf-buffer, not '" +
                                              data->media_type + "'");
                else if (data->base64 ? !valid_base64(data->payload, &decoded) : !percent_decoded_size(data->payload, &decoded))
                    problem(at(p, "uri"), "is not a valid data URI");
                else if (len && static_cast<int64_t>(decoded) != *len)
                    problem(p, "the data URI holds " + std::to_string(decoded) + " bytes but byteLength is " + std::to_string(*len));
            } else if (const std::string why = uri_problem(*uri); !why.empty()) {
                if (why.find("not supported") == std::string::npos) problem(at(p, "uri"), why);
                else {
                    warn(at(p, "uri"), why + "; its data is not available");
                    unavailable_buffers_.insert(i);
                }
            }
        } else if (!get(*b, "uri")) {
            if (!glb_ || i != 0) {
                // EXT_meshopt_compression's fallback buffer: its views' data come from decoding.
                const json* e = get(*b, "extensions");
                const json* m = e ? get(*e, "EXT_meshopt_compression") : nullptr;
                const json* f = m ? get(*m, "fallback") : nullptr;
                if (!(f && f->is_boolean() && f->get<bool>())) warn(p, "has no uri and is not a .glb's BIN chunk; its data is not available");
                unavailable_buffers_.insert(i);
            } else if (bin_ < 0) {
                problem(p, "refers to the .glb's BIN chunk, but the file has none");
            } else if (len && bin_ < *len) {
                problem(p, "byteLength " + std::to_string(*len) + " is larger than the BIN chunk (" + std::to_string(bin_) + " bytes)");
            } else if (len && bin_ - *len > 3) {
                warn(p, "the BIN chunk has " + std::to_string(bin_) + " bytes, more than byteLength " + std::to_string(*len) + " + padding");
            }
        }
    }
}

void Validator::check_buffer_views() {
    views_.assign(count("bufferViews"), ViewInfo{});
    // EXT_meshopt_compression on a bufferView (the extension's specification): where the compressed
    // bytes lie and how they decode into the view's byteLength. The loader decodes them
    // (gltf_meshopt.cpp); the view's own buffer is then not read, so the view is available even when
    // that buffer (a fallback buffer) has no data.
    auto check_meshopt_view = [&](const json& m, const std::string& p, ViewInfo& info) {
        const size_t before = issues_.size();
        const int64_t src = ref(m, "buffer", p, "buffers", true);
        const auto offset = integer(m, "byteOffset", p, false, 0);
        const auto length = integer(m, "byteLength", p, true, 1);
        const auto stride = integer(m, "byteStride", p, true, 1, 256);
        const auto n = integer(m, "count", p, true, 1);
        const std::string* mode = string(m, "mode", p, true);
        const std::string* filter = string(m, "filter", p, false);
        if (mode && *mode != "ATTRIBUTES" && *mode != "TRIANGLES" && *mode != "INDICES")
            problem(at(p, "mode"), "'" + *mode + "' is not ATTRIBUTES, TRIANGLES or INDICES");
        if (filter && *filter != "NONE" && *filter != "OCTAHEDRAL" && *filter != "QUATERNION" && *filter != "EXPONENTIAL")
            problem(at(p, "filter"), "'" + *filter + "' is not NONE, OCTAHEDRAL, QUATERNION or EXPONENTIAL");
        if (mode && stride) {
            if (*mode == "ATTRIBUTES" && *stride % 4 != 0) problem(at(p, "byteStride"), std::to_string(*stride) + " is not a multiple of 4 (mode ATTRIBUTES)");
            if (*mode != "ATTRIBUTES" && *stride != 2 && *stride != 4) problem(at(p, "byteStride"), std::to_string(*stride) + " is not 2 or 4 (mode " + *mode + ")");
            if (*mode == "TRIANGLES" && n && *n % 3 != 0) problem(at(p, "count"), std::to_string(*n) + " is not a multiple of 3 (mode TRIANGLES)");
            if (filter && *filter != "NONE" && *mode != "ATTRIBUTES") problem(at(p, "filter"), "'" + *filter + "' needs mode ATTRIBUTES");
            if (filter && *filter == "OCTAHEDRAL" && *stride != 4 && *stride != 8)
                problem(at(p, "byteStride"), std::to_string(*stride) + " is not 4 or 8 (filter OCTAHEDRAL)");
            if (filter && *filter == "QUATERNION" && *stride != 8) problem(at(p, "byteStride"), std::to_string(*stride) + " is not 8 (filter QUATERNION)");
        }
        if (n && stride && info.length > 0 && *n * *stride != info.length)
            problem(at(p, "count"), "count " + std::to_string(*n) + " x byteStride " + std::to_string(*stride) + " = " + std::to_string(*n * *stride) +
                                        " bytes, but the bufferView's byteLength is " + std::to_string(info.length));
        if (src >= 0 && length) {
            const int64_t blen = buffer_len_[static_cast<size_t>(src)];
            const int64_t off = offset.value_or(0);
            if (blen >= 0 && (off > blen || *length > blen - off))
                problem(at(p, "byteLength"), "byteOffset " + std::to_string(off) + " + byteLength " + std::to_string(*length) + " exceeds buffers[" +
                                                 std::to_string(src) + "].byteLength " + std::to_string(blen));
            if (unavailable_buffers_.count(static_cast<size_t>(src)))
                problem(at(p, "buffer"), "the compressed data lies in buffers[" + std::to_string(src) + "], whose data is not available");
        }
        if (issues_.size() == before) info.unavailable = false;
    };
    for (auto [i, v] : items("bufferViews")) {
        const std::string p = at("bufferViews", i);
        ViewInfo& info = views_[i];
        info.buffer = ref(*v, "buffer", p, "buffers", true);
        info.unavailable = unavailable_buffers_.count(static_cast<size_t>(std::max<int64_t>(info.buffer, 0))) && info.buffer >= 0;
        const auto offset = integer(*v, "byteOffset", p, false, 0);
        const auto length = integer(*v, "byteLength", p, true, 1);
        const auto stride = integer(*v, "byteStride", p, false, 4, 252);
        const auto target = integer(*v, "target", p, false, 0);
        if (stride && *stride % 4 != 0) problem(at(p, "byteStride"), std::to_string(*stride) + " is not a multiple of 4");
        if (target && *target != kArrayBuffer && *target != kElementArrayBuffer)
            warn(at(p, "target"), std::to_string(*target) + " is neither ARRAY_BUFFER (34962) nor ELEMENT_ARRAY_BUFFER (34963)");
        if (!length || info.buffer < 0 || (get(*v, "byteOffset") && !offset)) continue;
        info.offset = offset.value_or(0);
        info.length = *length;
        info.stride = stride.value_or(0);
        info.target = target.value_or(0);
        const int64_t blen = buffer_len_[static_cast<size_t>(info.buffer)];
        if (blen >= 0 && (info.offset > blen || info.length > blen - info.offset)) {
            problem(at(p, "byteLength"), "byteOffset " + std::to_string(info.offset) + " + byteLength " + std::to_string(info.length) +
                                             " exceeds buffers[" + std::to_string(info.buffer) + "].byteLength " + std::to_string(blen));
            continue;
        }
        if (info.stride > info.length)
            problem(at(p, "byteStride"), std::to_string(info.stride) + " is greater than byteLength " + std::to_string(info.length));
        if (info.stride && info.target == kElementArrayBuffer)
            problem(at(p, "byteStride"), "an index buffer view (target 34963) cannot have a byteStride");
        info.ok = !(get(*v, "byteStride") && !stride) && info.stride <= info.length;
        if (const json* e = get(*v, "extensions"); e && e->is_object())
            if (const json* m = get(*e, "EXT_meshopt_compression"); m && m->is_object()) check_meshopt_view(*m, at(at(p, "extensions"), "EXT_meshopt_compression"), info);
    }
}


// Bounds of `count` elements of `elem` bytes at `offset` in view `view` with `stride` (0 = packed).
void Validator::check_fits(int64_t view, int64_t offset, int64_t elem, int64_t stride, int64_t n, int64_t csize,
                           const std::string& path, int64_t last_elem) {
    if (view < 0 || !views_[static_cast<size_t>(view)].ok || n <= 0 || elem <= 0) return;
    const ViewInfo& v = views_[static_cast<size_t>(view)];
    if (csize > 0 && offset % csize != 0)
        problem(at(path, "byteOffset"), std::to_string(offset) + " is not a multiple of the component size " + std::to_string(csize));
    else if (csize > 0 && (v.offset + offset) % csize != 0)
        problem(path, "bufferView byteOffset + byteOffset (" + std::to_string(v.offset + offset) +
                          ") is not a multiple of the component size " + std::to_string(csize));
    const int64_t s = stride ? stride : elem;
    // The last element needs no padding after its last matrix column.
    const long double need = static_cast<long double>(offset) + static_cast<long double>(s) * static_cast<long double>(n - 1) +
                             (last_elem >= 0 ? last_elem : elem);
    if (need > static_cast<long double>(v.length)) {
        const std::string what = "accessor reads past the end of bufferView " + std::to_string(view) + " (needs " +
                                 num(static_cast<double>(need)) + " bytes from offset " + std::to_string(offset) + ", the view has " +
                                 std::to_string(v.length) + ")";
        if (out_of_bounds) *out_of_bounds = what;
        else problem(path, what);
    }
}

void Validator::check_accessors() {
    static const std::set<int64_t> types = {kByte, kUByte, kShort, kUShort, kUInt, kFloat};
    accessors_.assign(count("accessors"), AccessorInfo{});
    for (auto [i, a] : items("accessors")) {
        const std::string p = at("accessors", i);
        AccessorInfo& info = accessors_[i];
        bool ok = true;
        info.view = ref(*a, "bufferView", p, "bufferViews", false);
        ok = ok && !(get(*a, "bufferView") && info.view < 0);
        info.unavailable = info.view >= 0 && views_[static_cast<size_t>(info.view)].unavailable;
        const auto offset = integer(*a, "byteOffset", p, false, 0);
        if (get(*a, "byteOffset") && !get(*a, "bufferView")) problem(at(p, "byteOffset"), "is set but there is no bufferView");
        const auto ct = integer(*a, "componentType", p, true, 0);
        // An unknown enum value is not an error by itself (glTF-Validator: VALUE_NOT_IN_LIST is a
        // warning); reading such an accessor is (see unusable()).
        if (ct && !types.count(*ct)) {
            warn(at(p, "componentType"), std::to_string(*ct) + " is not a glTF component type; the accessor is unusable");
            info.unknown_format = true;
            ok = false;
        }
        const std::string* type = string(*a, "type", p, true);
        if (type && !type_components(*type)) {
            warn(at(p, "type"), "'" + *type + "' is not SCALAR, VEC2, VEC3, VEC4, MAT2, MAT3 or MAT4; the accessor is unusable");
            info.unknown_format = true;
            ok = false;
        }
        const auto n = integer(*a, "count", p, true, 1);
        bool normalized = false;
        if (const json* nv = get(*a, "normalized")) {
            if (!nv->is_boolean()) problem(at(p, "normalized"), "must be true or false");
            else normalized = nv->get<bool>();
        }
        if (!ct || !type || !n || (get(*a, "byteOffset") && !offset) || !ok) continue;
        info.component_type = *ct;
        info.type = *type;
        info.components = type_components(*type);
        info.normalized = normalized;
        info.count = *n;
        info.offset = offset.value_or(0);
        if (normalized && (*ct == kFloat || *ct == kUInt)) {
            problem(at(p, "normalized"), std::string("only BYTE, UNSIGNED_BYTE, SHORT and UNSIGNED_SHORT can be normalized, not ") +
                                             component_name(*ct));
            continue;
        }
        for (const char* key : {"min", "max"})
            if (const json* mm = numbers(*a, key, p, static_cast<size_t>(info.components))) {
                (std::strcmp(key, "min") == 0 ? info.has_min : info.has_max) = true;
                (void)mm;
            }
        const int64_t csize = component_size(*ct);
        const int64_t elem = element_size(*ct, *type);
        if ((*type == "MAT2" || *type == "MAT3") && csize < 4 && info.offset % 4 != 0)
            problem(at(p, "byteOffset"), "matrix accessors must start on a 4-byte boundary");
        if (info.view >= 0 && views_[static_cast<size_t>(info.view)].ok) {
            const ViewInfo& v = views_[static_cast<size_t>(info.view)];
            if (v.stride && v.stride < elem) {
                problem(p, "bufferView " + std::to_string(info.view) + " byteStride " + std::to_string(v.stride) +
                               " is smaller than the element (" + std::to_string(elem) + " bytes)");
                continue;
            }
            const size_t before = issues_.size();
            const int64_t rows = *type == "MAT2" ? 2 : *type == "MAT3" ? 3 : 0;
            const int64_t last = rows ? elem - (elem / rows - rows * csize) : elem;
            out_of_bounds = &info.out_of_bounds;
            check_fits(info.view, info.offset, elem, v.stride, info.count, csize, p, last);
            out_of_bounds = nullptr;
            if (issues_.size() != before) continue;
        }
        if (const json* s = get(*a, "sparse")) {
            const std::string sp = at(p, "sparse");
            if (!s->is_object()) {
                problem(sp, "must be an object");
                continue;
            }
            const auto sn = integer(*s, "count", sp, true, 1);
            if (sn && *sn > info.count)
                problem(at(sp, "count"), std::to_string(*sn) + " is more than the accessor's count " + std::to_string(info.count));
            for (const char* part : {"indices", "values"}) {
                const json* o = get(*s, part);
                const std::string pp = at(sp, part);
                if (!o || !o->is_object()) {
                    problem(sp, std::string("'") + part + "' must be an object");
                    continue;
                }
                const int64_t view = ref(*o, "bufferView", pp, "bufferViews", true);
                const auto off = integer(*o, "byteOffset", pp, false, 0);
                int64_t e = elem, cs = csize;
                if (std::strcmp(part, "indices") == 0) {
                    const auto ict = integer(*o, "componentType", pp, true, 0);
                    if (ict && *ict != kUByte && *ict != kUShort && *ict != kUInt) {
                        problem(at(pp, "componentType"), std::string(component_name(*ict)) + " is not an index type (UNSIGNED_BYTE, _SHORT or _INT)");
                        continue;
                    }
                    if (!ict) continue;
                    e = cs = component_size(*ict);
                }
                if (view >= 0 && views_[static_cast<size_t>(view)].stride)
                    problem(at(pp, "bufferView"), "bufferView " + std::to_string(view) + " of sparse data cannot have a byteStride");
                if (sn && *sn <= info.count) check_fits(view, off.value_or(0), e, 0, *sn, cs, pp);
            }
        }
        info.ok = true;
    }
}

}  // namespace candela::gltf::validation

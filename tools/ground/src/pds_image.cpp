#include "vtm/ground/pds_image.hpp"

#include <filesystem>
#include <system_error>

#include "file_bytes.hpp"
#include "pds_fields.hpp"

namespace vtm::ground {
namespace {

using detail::PdsFields;

struct SampleFormat {
    std::int32_t bytes = 0;
    bool big_endian = true;
    bool is_signed = false;
};

// The SAMPLE_TYPE / SAMPLE_BITS pairs read; false for anything else.
bool sampleFormat(const std::string& type, std::int32_t bits, SampleFormat& out) {
    if (bits == 8 && (type == "UNSIGNED_INTEGER" || type == "MSB_UNSIGNED_INTEGER" || type == "LSB_UNSIGNED_INTEGER")) {
        out = SampleFormat{1, true, false};
        return true;
    }
    if (bits != 16) return false;
    if (type == "MSB_INTEGER" || type == "INTEGER") out = SampleFormat{2, true, true};
    else if (type == "MSB_UNSIGNED_INTEGER" || type == "UNSIGNED_INTEGER") out = SampleFormat{2, true, false};
    else if (type == "LSB_INTEGER") out = SampleFormat{2, false, true};
    else if (type == "LSB_UNSIGNED_INTEGER") out = SampleFormat{2, false, false};
    else return false;
    return true;
}

// ^IMAGE: "N" (1-based record) or "N <BYTES>" (1-based byte); a file name is refused.
std::string imageOffset(const PdsFields& f, std::uint64_t& record_bytes, std::uint64_t& offset) {
    const PdsStatement* pointer = f.label.find("", "^IMAGE");
    if (pointer == nullptr) return f.missing("", "^IMAGE");
    const std::string& v = pointer->value;
    if (!v.empty() && (v.front() == '(' || v.front() == '"')) {
        return f.bad(*pointer, "names a separate file; only labels attached to their image are read");
    }
    std::uint64_t n = 0;
    if (!pdsUnsigned(v, std::uint64_t{1} << 40, n) || n == 0U) return f.bad(*pointer, "must be a positive integer");
    if (v.find('<') != std::string::npos) {
        if (v.find("<BYTES>") == std::string::npos) return f.bad(*pointer, "unit must be <BYTES> or none (records)");
        offset = n - 1U;
        return "";
    }
    const std::string e = f.unsignedField("", "RECORD_BYTES", 1U, std::uint64_t{1} << 20, record_bytes);
    if (!e.empty()) return e;
    offset = (n - 1U) * record_bytes;  // < 2^60
    return "";
}

std::string imageObject(const PdsFields& f, PdsImageInfo& info) {
    std::uint64_t lines = 0, samples = 0, bits = 0, bands = 1, prefix = 0, suffix = 0;
    std::string e = f.unsignedField("IMAGE", "LINES", 1U, kMaxPdsImageSide, lines);
    if (e.empty()) e = f.unsignedField("IMAGE", "LINE_SAMPLES", 1U, kMaxPdsImageSide, samples);
    if (e.empty()) e = f.unsignedField("IMAGE", "SAMPLE_BITS", 1U, 64U, bits);
    if (e.empty() && f.label.find("IMAGE", "BANDS") != nullptr) e = f.unsignedField("IMAGE", "BANDS", 1U, 1U, bands);
    if (e.empty() && f.label.find("IMAGE", "LINE_PREFIX_BYTES") != nullptr) {
        e = f.unsignedField("IMAGE", "LINE_PREFIX_BYTES", 0U, 0U, prefix);
    }
    if (e.empty() && f.label.find("IMAGE", "LINE_SUFFIX_BYTES") != nullptr) {
        e = f.unsignedField("IMAGE", "LINE_SUFFIX_BYTES", 0U, 0U, suffix);
    }
    if (!e.empty()) return e;
    const PdsStatement* type = f.label.find("IMAGE", "SAMPLE_TYPE");
    if (type == nullptr) return f.missing("IMAGE", "SAMPLE_TYPE");
    info.lines = static_cast<std::int32_t>(lines);
    info.line_samples = static_cast<std::int32_t>(samples);
    info.sample_bits = static_cast<std::int32_t>(bits);
    info.sample_type = pdsText(type->value);
    SampleFormat format;
    if (!sampleFormat(info.sample_type, info.sample_bits, format)) {
        return f.bad(*type, "with SAMPLE_BITS " + std::to_string(bits) +
                                " is not read (8-bit unsigned or 16-bit integer samples are)");
    }
    return "";
}

PdsPointing pointing(const PdsLabel& label, const std::string& group) {
    PdsPointing p;
    const PdsStatement* az = label.find(group, "INSTRUMENT_AZIMUTH");
    const PdsStatement* el = label.find(group, "INSTRUMENT_ELEVATION");
    p.valid = az != nullptr && el != nullptr && pdsReal(az->value, p.azimuth_deg) && pdsReal(el->value, p.elevation_deg);
    if (!p.valid) p = PdsPointing{};
    return p;
}

std::string textOf(const PdsLabel& label, const std::string& scope, const std::string& key) {
    const PdsStatement* s = label.find(scope, key);
    return s != nullptr ? pdsText(s->value) : std::string();
}

std::string decodeSamples(const std::vector<unsigned char>& bytes, const PdsImageInfo& info, const std::string& name,
                          Grey16Image& out) {
    SampleFormat format;
    (void)sampleFormat(info.sample_type, info.sample_bits, format);  // checked by pdsImageInfo
    const std::uint64_t size = static_cast<std::uint64_t>(info.lines) * static_cast<std::uint64_t>(info.line_samples) *
                               static_cast<std::uint64_t>(format.bytes);
    if (info.image_offset > bytes.size() || size > bytes.size() - info.image_offset) {
        return name + ": truncated PDS image: the " + std::to_string(info.line_samples) + " x " +
               std::to_string(info.lines) + " samples need bytes " + std::to_string(info.image_offset) + ".." +
               std::to_string(info.image_offset + size - 1U) + ", the file has " + std::to_string(bytes.size());
    }
    out = Grey16Image(info.line_samples, info.lines);
    const unsigned char* p = bytes.data() + info.image_offset;
    for (std::int32_t y = 0; y < info.lines; ++y) {
        for (std::int32_t x = 0; x < info.line_samples; ++x, p += format.bytes) {
            std::uint32_t v = p[0];
            if (format.bytes == 2) {
                v = format.big_endian ? (v << 8U) | p[1] : (static_cast<std::uint32_t>(p[1]) << 8U) | v;
            }
            if (format.is_signed && (v & 0x8000U) != 0U) {
                return name + ": PDS image: sample at line " + std::to_string(y + 1) + ", sample " +
                       std::to_string(x + 1) + " is negative (" + std::to_string(static_cast<std::int32_t>(v) - 65536) +
                       "); " + info.sample_type + " images with negative samples are not read";
            }
            out.at(x, y) = static_cast<std::uint16_t>(v);
        }
    }
    return "";
}

bool isSupportedModel(const std::string& type) { return type == "CAHV" || type == "CAHVOR"; }

}  // namespace

Result<PdsImageInfo> pdsImageInfo(const PdsLabel& label, const std::string& name) {
    const PdsFields f{label, name};
    PdsImageInfo info;
    std::string e = imageOffset(f, info.record_bytes, info.image_offset);
    if (e.empty()) e = imageObject(f, info);
    if (!e.empty()) return Result<PdsImageInfo>::failure(e);
    info.instrument_id = textOf(label, "", "INSTRUMENT_ID");
    info.start_time = textOf(label, "", "START_TIME");
    info.product_id = textOf(label, "", "PRODUCT_ID");
    const std::string model_group = detail::pdsCameraModelGroup(label);
    if (!model_group.empty()) {
        info.model_type = textOf(label, model_group, "MODEL_TYPE");
        info.model_frame = textOf(label, model_group, "REFERENCE_COORD_SYSTEM_NAME");
    }
    info.rover_pointing = pointing(label, "ROVER_DERIVED_GEOMETRY_PARMS");
    info.site_pointing = pointing(label, "SITE_DERIVED_GEOMETRY_PARMS");
    return Result<PdsImageInfo>::success(std::move(info));
}

Result<PdsImage> decodePdsImage(const std::vector<unsigned char>& bytes, const std::string& name,
                                const PdsReadOptions& options) {
    const Result<PdsLabel> label = parsePdsLabel(bytes, name);
    if (!label.ok) return Result<PdsImage>::failure(label.error);
    Result<PdsImageInfo> info = pdsImageInfo(label.value, name);
    if (!info.ok) return Result<PdsImage>::failure(info.error);
    PdsImage image;
    image.info = std::move(info.value);
    if (isSupportedModel(image.info.model_type) || options.require_camera_model) {
        const Result<CameraModel> model =
            pdsCameraModel(label.value, image.info.line_samples, image.info.lines, name);
        if (!model.ok) return Result<PdsImage>::failure(model.error);
        image.camera_model = model.value;
        image.has_camera_model = true;
    }
    if (detail::pdsHasRoverFrame(label.value) || options.require_rover_pose) {
        const Result<RigidPose> pose = pdsSiteFromRover(label.value, name);
        if (!pose.ok) return Result<PdsImage>::failure(pose.error);
        image.site_from_rover = pose.value;
        image.has_rover_pose = true;
    }
    const std::string e = decodeSamples(bytes, image.info, name, image.pixels);
    if (!e.empty()) return Result<PdsImage>::failure(e);
    return Result<PdsImage>::success(std::move(image));
}

Result<PdsImage> readPdsImage(const std::string& path, const PdsReadOptions& options) {
    std::error_code ec;
    const std::uintmax_t size = std::filesystem::file_size(path, ec);
    if (!ec && size > kMaxPdsFileBytes) {
        return Result<PdsImage>::failure(path + ": PDS file of " + std::to_string(size) + " bytes, over the " +
                                         std::to_string(kMaxPdsFileBytes) + " accepted");
    }
    const Result<detail::Bytes> bytes = detail::readFileBytes(path);
    if (!bytes.ok) return Result<PdsImage>::failure(bytes.error);
    return decodePdsImage(bytes.value, path, options);
}

GreyImage pdsStretchToGrey8(const Grey16Image& image, double low_fraction, double high_fraction) {
    GreyImage out(image.width, image.height);
    if (image.pixels.empty()) return out;
    std::vector<std::uint64_t> histogram(65536U, 0U);
    for (const std::uint16_t v : image.pixels) ++histogram[v];
    const auto n = static_cast<double>(image.pixels.size());
    const double lo_f = low_fraction >= 0.0 && low_fraction <= 1.0 ? low_fraction : 0.0;
    const double hi_f = high_fraction >= lo_f && high_fraction <= 1.0 ? high_fraction : 1.0;
    const auto lo_count = static_cast<std::uint64_t>(lo_f * n);        // samples below lo: at most this
    const auto hi_count = static_cast<std::uint64_t>(hi_f * n + 0.5);  // samples up to hi: at least this
    std::uint64_t cumulative = 0;
    std::int64_t lo = -1, hi = -1;
    for (std::int64_t v = 0; v < 65536; ++v) {
        cumulative += histogram[static_cast<std::size_t>(v)];
        if (lo < 0 && cumulative > lo_count) lo = v;
        if (hi < 0 && cumulative >= hi_count && cumulative > 0U) hi = v;
    }
    if (hi <= lo) hi = lo + 1;
    const std::int64_t range = hi - lo;
    for (std::size_t i = 0; i < image.pixels.size(); ++i) {
        const std::int64_t v = static_cast<std::int64_t>(image.pixels[i]) - lo;
        const std::int64_t scaled = v <= 0 ? 0 : (v >= range ? 255 : (v * 255 + range / 2) / range);
        out.pixels[i] = static_cast<std::uint8_t>(scaled);
    }
    return out;
}

}  // namespace vtm::ground

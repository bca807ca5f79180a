#include "scene_file.h"

#include <glm/gtc/type_ptr.hpp>

#include <cerrno>
#include <cstddef>
#include <cstring>
#include <fstream>
#include <iterator>
#include <type_traits>
#include <vector>

#include "renderer.h"
#include "util/error.h"

namespace subsplat {

namespace {

constexpr char kMagic[8] = {'S', 'S', 'S', 'C', 'E', 'N', 'E', '\0'};
constexpr uint32_t kFormatVersion = 9;
// Format 1 is format 2 with a shorter settings record (no target_error: the default); formats 1
// and 2 have a shorter material record (no profile_model: the dipole); formats 1 to 3 a shorter
// light record (no world_directions and area fields: there were no world and area lights); formats
// 2 to 4 a shorter settings record (no anti-aliasing fields: one sample at the pixel's centre);
// formats 1 to 5 have no textures in the material record; formats 4 to 6 a shorter light record (no
// world_sh: a world of two halves); formats 5 to 7 a shorter settings record (no precomputed_atlas:
// the UV map where it fits); format 8 a shorter one again (no forward_shift: on, the default).
constexpr uint32_t kOldestFormatVersion = 1;
constexpr size_t kSettingsBytesV1 = 14 * 4, kSettingsBytesV4 = 15 * 4, kSettingsBytesV7 = 19 * 4, kSettingsBytesV8 = 20 * 4;
enum Tag : uint32_t { kMaterial = 1, kMesh = 2, kLights = 3, kCamera = 4, kSettings = 5, kFrame = 6, kEnvironment = 7 };
constexpr uint32_t kMeshHasUvs = 1;

// The API structs are written as they lie in memory: 4-byte fields only, no
// padding (asserted), little-endian (the only byte order the library builds for).
// A material record holds SsMaterialDesc up to profile_model (kMaterialBytes),
// then for SUBEDIT the profile set: n, r_s, palette and map; then (format 6) the colour and normal
// textures (each: present, and if so its transform, modes, size and texels) and the normal strength.
constexpr size_t kMaterialBytes = 15 * 4;
constexpr size_t kMaterialBytesV2 = 14 * 4;
constexpr size_t kLightBytes = 51 * 4, kLightBytesV6 = 24 * 4, kLightBytesV3 = 13 * 4;
static_assert(offsetof(SsMaterialDesc, profile_model) + 4 == kMaterialBytes &&
                  offsetof(SsMaterialDesc, profile_model) == kMaterialBytesV2 &&
                  offsetof(SsMaterialDesc, profiles) == kMaterialBytes + 4 /* padding */ && sizeof(SsLightDesc) == kLightBytes &&
                  offsetof(SsLightDesc, world_directions) == kLightBytesV3 &&
                  offsetof(SsLightDesc, world_sh) == kLightBytesV6 &&
                  sizeof(SsCameraDesc) == 33 * 4 && sizeof(SsSettings) == 21 * 4 &&
                  offsetof(SsSettings, precomputed_atlas) == kSettingsBytesV7 &&
                  offsetof(SsSettings, forward_shift) == kSettingsBytesV8 &&
                  offsetof(SsSettings, target_error) == kSettingsBytesV1 &&
                  offsetof(SsSettings, samples) == kSettingsBytesV4,
              "scene file records mirror the API structs; bump kFormatVersion when they change");
static_assert(__BYTE_ORDER__ == __ORDER_LITTLE_ENDIAN__, "scene files are little-endian");

class Writer {
 public:
  template <typename T>
  void put(const T& value) {
    static_assert(std::is_trivially_copyable_v<T>);
    const char* p = reinterpret_cast<const char*>(&value);
    bytes_.insert(bytes_.end(), p, p + sizeof(T));
  }
  template <typename T>
  void putArray(const std::vector<T>& values) {
    const char* p = reinterpret_cast<const char*>(values.data());
    bytes_.insert(bytes_.end(), p, p + values.size() * sizeof(T));
  }
  // A record: tag, payload size, payload written by `body`.
  template <typename F>
  void record(Tag tag, F&& body) {
    put(uint32_t(tag));
    put(uint32_t(0));
    size_t sizeAt = bytes_.size();
    put(uint64_t(0));
    body();
    uint64_t size = bytes_.size() - sizeAt - sizeof(uint64_t);
    std::memcpy(bytes_.data() + sizeAt, &size, sizeof size);
  }
  const std::vector<char>& bytes() const { return bytes_; }

 private:
  std::vector<char> bytes_;
};

class Reader {
 public:
  Reader(const char* data, size_t size, std::string what) : data_(data), size_(size), what_(std::move(what)) {}
  template <typename T>
  T get() {
    T value;
    take(&value, sizeof(T));
    return value;
  }
  template <typename T>
  std::vector<T> getArray(size_t count) {
    require(count <= remaining() / sizeof(T), what_ + ": truncated (" + std::to_string(count) +
                                                    " elements announced, " + std::to_string(remaining()) +
                                                    " bytes left)");
    std::vector<T> values(count);
    take(values.data(), count * sizeof(T));
    return values;
  }
  size_t remaining() const { return size_ - at_; }
  const std::string& what() const { return what_; }

 private:
  void take(void* out, size_t n) {
    require(n <= remaining(), what_ + ": truncated");
    std::memcpy(out, data_ + at_, n);
    at_ += n;
  }
  const char* data_;
  size_t size_, at_ = 0;
  std::string what_;
};

std::string systemError() { return std::strerror(errno); }

template <typename T>
std::vector<float> flatten(const std::vector<T>& v) {
  std::vector<float> out;
  out.reserve(v.size() * T::length());
  for (const T& x : v)
    for (int i = 0; i < T::length(); ++i) out.push_back(x[i]);
  return out;
}

void readMesh(Scene& scene, Reader& r) {
  uint32_t id = r.get<uint32_t>(), vertexCount = r.get<uint32_t>(), triangleCount = r.get<uint32_t>();
  uint32_t flags = r.get<uint32_t>();
  SsMeshDesc desc{};
  for (float& m : desc.object_to_world) m = r.get<float>();
  std::vector<float> positions = r.getArray<float>(3 * size_t(vertexCount));
  std::vector<float> normals = r.getArray<float>(3 * size_t(vertexCount));
  std::vector<float> uvs;
  if (flags & kMeshHasUvs) uvs = r.getArray<float>(2 * size_t(vertexCount));
  std::vector<uint32_t> indices = r.getArray<uint32_t>(3 * size_t(triangleCount));
  std::vector<uint32_t> materials = r.getArray<uint32_t>(triangleCount);
  desc.positions = positions.data();
  desc.normals = normals.data();
  desc.uvs = uvs.empty() ? nullptr : uvs.data();
  desc.vertex_count = vertexCount;
  desc.indices = indices.data();
  desc.triangle_materials = materials.data();
  desc.triangle_count = triangleCount;
  scene.setMesh(id, desc);
}

// An image as the writer puts it: width u32, height u32, texels (3 f32 each), checked as ssNewImage
// checks it; `what` names it in the messages.
std::shared_ptr<const TextureImage> readImage(Reader& r, const char* what) {
  SsImageDesc image{};
  image.width = r.get<uint32_t>();
  image.height = r.get<uint32_t>();
  require(image.width >= 1 && image.height >= 1 && image.width <= TextureImage::kMaxSide &&
              image.height <= TextureImage::kMaxSide,
          r.what() + ": " + what + " size out of range");
  std::vector<float> texels = r.getArray<float>(3 * size_t(image.width) * size_t(image.height));
  image.rgb = texels.data();
  try {
    return std::make_shared<const TextureImage>(image);
  } catch (const Error& e) {
    fail(e.status(), r.what() + ": " + what + ": " + e.what());
  }
}

void readMaterial(Scene& scene, Reader& r, uint32_t version) {
  uint32_t id = r.get<uint32_t>();
  SsMaterialDesc desc{};
  std::vector<char> bytes = r.getArray<char>(version >= 3 ? kMaterialBytes : kMaterialBytesV2);
  std::memcpy(&desc, bytes.data(), bytes.size());
  std::shared_ptr<const ProfileSet> profiles;
  if (desc.kind == SS_MATERIAL_SUBEDIT) {
    int32_t segments = r.get<int32_t>();
    float radius = r.get<float>();
    int32_t count = r.get<int32_t>(), width = r.get<int32_t>(), height = r.get<int32_t>();
    require(segments >= 1 && segments <= ProfileSet::kMaxSegments && count >= 1 &&
                count <= ProfileSet::kMaxProfiles && width >= 1 && height >= 1 && width <= ProfileSet::kMaxSide &&
                height <= ProfileSet::kMaxSide,
            r.what() + ": profile set sizes out of range");
    std::vector<float> palette = r.getArray<float>(size_t(count) * size_t(segments + 1) * 3);
    std::vector<uint16_t> map = r.getArray<uint16_t>(size_t(width) * size_t(height));
    try {
      profiles = std::make_shared<const ProfileSet>(
          ProfileSet::fromPalette(segments, radius, std::move(palette), width, height, std::move(map), {}));
    } catch (const Error& e) {
      fail(e.status(), r.what() + ": " + e.what());
    }
  }
  std::shared_ptr<const TextureImage> images[2];
  if (version >= 6) {
    SsTextureDesc* textures[2] = {&desc.color_texture, &desc.normal_texture};
    for (int k = 0; k < 2; ++k) {
      if (r.get<int32_t>() == 0) continue;
      SsTextureDesc& t = *textures[k];
      for (float& v : t.transform) v = r.get<float>();
      t.extension = r.get<int32_t>();
      t.interpolation = r.get<int32_t>();
      images[k] = readImage(r, "texture");
      t.image = reinterpret_cast<SsImage>(1);  // present; the image itself goes by images[k]
    }
    desc.normal_strength = r.get<float>();
  }
  scene.setMaterial(id, desc, std::move(profiles), images[0], images[1]);
}

FrameSize readRecords(Scene& scene, const std::function<void(const SsSettings&)>& applySettings,
                      const std::vector<char>& bytes, const std::string& path) {
  FrameSize frame;
  Reader file(bytes.data(), bytes.size(), path);
  char magic[8];
  for (char& c : magic) c = file.get<char>();
  require(std::memcmp(magic, kMagic, sizeof magic) == 0, path + " is not a subsplat scene file");
  uint32_t version = file.get<uint32_t>();
  require(version >= kOldestFormatVersion && version <= kFormatVersion,
          path + ": scene file format " + std::to_string(version) + " is not supported (this library reads formats " +
              std::to_string(kOldestFormatVersion) + " to " + std::to_string(kFormatVersion) + ")");
  file.get<uint32_t>();  // API version that wrote it, informational
  int index = 0;
  while (file.remaining() > 0) {
    uint32_t tag = file.get<uint32_t>();
    file.get<uint32_t>();
    uint64_t size = file.get<uint64_t>();
    require(size <= file.remaining(), path + ": record " + std::to_string(index) + " is truncated");
    std::vector<char> payload = file.getArray<char>(size);
    Reader r(payload.data(), payload.size(), path + ", record " + std::to_string(index));
    switch (tag) {
      case kMaterial:
        readMaterial(scene, r, version);
        break;
      case kMesh:
        readMesh(scene, r);
        break;
      case kLights: {
        uint32_t count = r.get<uint32_t>();
        std::vector<SsLightDesc> lights(count, SsLightDesc{});
        size_t bytes = version >= 7 ? kLightBytes : version >= 4 ? kLightBytesV6 : kLightBytesV3;
        require(count <= r.remaining() / bytes, r.what() + ": truncated (" + std::to_string(count) + " lights announced)");
        for (SsLightDesc& light : lights) {
          std::vector<char> record = r.getArray<char>(bytes);
          std::memcpy(&light, record.data(), bytes);
        }
        scene.setLights(lights.data(), count);
        break;
      }
      case kCamera:
        scene.setCamera(r.get<SsCameraDesc>());
        break;
      case kSettings: {
        SsSettings settings{};
        if (version <= 8) {
          std::vector<char> old = r.getArray<char>(version == 1   ? kSettingsBytesV1
                                                   : version <= 4 ? kSettingsBytesV4
                                                   : version <= 7 ? kSettingsBytesV7
                                                                  : kSettingsBytesV8);
          std::memcpy(&settings, old.data(), old.size());
        } else {
          settings = r.get<SsSettings>();
        }
        applySettings(settings);
        break;
      }
      case kEnvironment: {  // format 6
        SsEnvironmentDesc desc{};
        desc.strength = r.get<float>();
        for (float& v : desc.rotation) v = r.get<float>();
        scene.setEnvironment(desc, readImage(r, "environment"));
        break;
      }
      case kFrame:
        frame.width = r.get<int32_t>();
        frame.height = r.get<int32_t>();
        require(frame.width > 0 && frame.height > 0 && frame.width <= 65536 && frame.height <= 65536,
                r.what() + ": frame size out of range");
        break;
      default:
        break;  // a newer writer's record: skipped, so that old readers keep working
    }
    require(r.remaining() == 0, r.what() + ": " + std::to_string(r.remaining()) + " bytes past its end");
    ++index;
  }
  return frame;
}

}  // namespace

void saveScene(const Scene& scene, const SsSettings& settings, FrameSize frame, const std::string& path) {
  Writer w;
  for (char c : kMagic) w.put(c);
  w.put(kFormatVersion);
  w.put(uint32_t(SS_API_VERSION));
  // (Named copies of the bindings: lambdas may not capture structured bindings before C++20.)
  for (const auto& entry : scene.materials()) {
    const auto& [id, material] = entry;
    w.record(kMaterial, [&, id = id, &material = material] {
      w.put(id);
      const char* desc = reinterpret_cast<const char*>(&material.desc);
      for (size_t i = 0; i < kMaterialBytes; ++i) w.put(desc[i]);
      if (material.profiles) {
        const ProfileSet& set = *material.profiles;
        w.put(int32_t(set.segments()));
        w.put(float(set.radiusMm()));
        w.put(int32_t(set.profileCount()));
        w.put(int32_t(set.width()));
        w.put(int32_t(set.height()));
        w.putArray(set.palette());
        w.putArray(set.map());
      }
      for (const Texture* t : {&material.color, &material.normal}) {
        w.put(int32_t(bool(*t)));
        if (!*t) continue;
        for (float v : t->transform) w.put(v);
        w.put(t->extension);
        w.put(t->interpolation);
        w.put(uint32_t(t->image->width()));
        w.put(uint32_t(t->image->height()));
        w.putArray(flatten(t->image->texels()));
      }
      w.put(material.desc.normal_strength);
    });
  }
  for (const auto& entry : scene.meshes()) {
    const auto& [id, mesh] = entry;
    w.record(kMesh, [&, id = id, &mesh = mesh] {
      w.put(id);
      w.put(uint32_t(mesh.cpuPositions.size()));
      w.put(mesh.triangleCount);
      w.put(uint32_t(mesh.cpuUvs.empty() ? 0 : kMeshHasUvs));
      for (int i = 0; i < 16; ++i) w.put(glm::value_ptr(mesh.objectToWorld)[i]);
      w.putArray(flatten(mesh.cpuPositions));
      w.putArray(flatten(mesh.cpuNormals));
      if (!mesh.cpuUvs.empty()) w.putArray(flatten(mesh.cpuUvs));
      w.putArray(mesh.cpuIndices);
      w.putArray(mesh.materialIds);
    });
  }
  w.record(kLights, [&] {
    w.put(uint32_t(scene.lights().size()));
    w.putArray(scene.lights());
  });
  if (scene.hasCamera()) w.record(kCamera, [&] { w.put(scene.camera()); });
  if (const Environment& environment = scene.environment(); environment)
    w.record(kEnvironment, [&] {
      w.put(environment.strength);
      for (int c = 0; c < 3; ++c)
        for (int r = 0; r < 3; ++r) w.put(environment.rotation[c][r]);
      w.put(uint32_t(environment.image->width()));
      w.put(uint32_t(environment.image->height()));
      w.putArray(flatten(environment.image->texels()));
    });
  w.record(kSettings, [&] { w.put(settings); });
  if (frame.width > 0)
    w.record(kFrame, [&] {
      w.put(int32_t(frame.width));
      w.put(int32_t(frame.height));
    });

  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  if (!out) fail(SS_INVALID_ARGUMENT, "cannot write " + path + ": " + systemError());
  out.write(w.bytes().data(), std::streamsize(w.bytes().size()));
  out.close();
  if (!out) fail(SS_INVALID_ARGUMENT, "writing " + path + " failed: " + systemError());
}

FrameSize loadScene(Scene& scene, const std::function<void(const SsSettings&)>& applySettings,
                    const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) fail(SS_INVALID_ARGUMENT, "cannot read " + path + ": " + systemError());
  std::vector<char> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (in.bad()) fail(SS_INVALID_ARGUMENT, "reading " + path + " failed: " + systemError());
  scene.clear();
  try {
    return readRecords(scene, applySettings, bytes, path);
  } catch (...) {
    scene.clear();
    throw;
  }
}

void saveScene(const Renderer& renderer, const std::string& path) {
  saveScene(renderer.scene(), renderer.settings(), {renderer.lastWidth(), renderer.lastHeight()}, path);
}

FrameSize loadScene(Renderer& renderer, const std::string& path) {
  return loadScene(renderer.scene(), [&](const SsSettings& settings) { renderer.setSettings(settings); }, path);
}

}  // namespace subsplat

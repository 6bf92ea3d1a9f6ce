#include "io/asset_stream.h"

#include <cstdint>
#include <cstring>
#include <type_traits>

namespace mlod {

namespace {

constexpr char kMagic[8] = {'M', 'L', 'O', 'D', 'A', 'S', 'T', '1'};

class Writer {
public:
  explicit Writer(const AssetStreamSink& sink) : m_sink(sink) {}
  bool ok() const { return m_ok; }
  void bytes(const void* data, std::size_t size) {
    if (size == 0)
      return; // an empty vector's data() may be null
    if (size >= kGather) { // large arrays go straight to the sink, after what is gathered
      flush();
      if (m_ok)
        m_ok = m_sink(static_cast<const char*>(data), size);
      return;
    }
    m_buffer.append(static_cast<const char*>(data), size);
    if (m_buffer.size() >= kGather)
      flush();
  }
  template <typename T>
  void pod(const T& value) {
    static_assert(std::is_trivially_copyable_v<T>);
    bytes(&value, sizeof(T));
  }
  void text(const std::string& value) {
    pod(static_cast<std::uint64_t>(value.size()));
    bytes(value.data(), value.size());
  }
  template <typename T>
  void array(const std::vector<T>& values) {
    static_assert(std::is_trivially_copyable_v<T>);
    pod(static_cast<std::uint64_t>(values.size()));
    bytes(values.data(), values.size() * sizeof(T));
  }
  void flush() {
    if (m_ok && !m_buffer.empty())
      m_ok = m_sink(m_buffer.data(), m_buffer.size());
    m_buffer.clear();
  }

private:
  static constexpr std::size_t kGather = std::size_t(1) << 20;
  const AssetStreamSink& m_sink;
  std::string m_buffer;
  bool m_ok = true;
};

class Reader {
public:
  explicit Reader(std::string_view in) : m_in(in) {}
  bool failed() const { return m_failed; }
  template <typename T>
  T pod() {
    T value{};
    if (!take(&value, sizeof(T)))
      m_failed = true;
    return value;
  }
  std::string text() {
    const auto size = pod<std::uint64_t>();
    if (m_failed || size > m_in.size() - m_offset) {
      m_failed = true;
      return {};
    }
    std::string value(m_in.substr(m_offset, size));
    m_offset += size;
    return value;
  }
  template <typename T>
  std::vector<T> array() {
    const auto count = pod<std::uint64_t>();
    if (m_failed || count > (m_in.size() - m_offset) / sizeof(T)) {
      m_failed = true;
      return {};
    }
    std::vector<T> values(count);
    take(values.data(), count * sizeof(T));
    return values;
  }

private:
  bool take(void* out, std::size_t size) {
    if (size == 0)
      return true; // an empty vector's data() may be null, and memcpy must not see it
    if (size > m_in.size() - m_offset)
      return false;
    std::memcpy(out, m_in.data() + m_offset, size);
    m_offset += size;
    return true;
  }
  std::string_view m_in;
  std::size_t m_offset = 0;
  bool m_failed = false;
};

} // namespace

void writeAssetStream(const Asset& asset, std::string& out_bytes) {
  writeAssetStream(asset, [&out_bytes](const char* data, std::size_t size) {
    out_bytes.append(data, size);
    return true;
  });
}

bool writeAssetStream(const Asset& asset, const AssetStreamSink& sink) {
  Writer w(sink);
  w.bytes(kMagic, sizeof(kMagic));
  w.text(asset.sourcePath);
  w.text(asset.format);
  w.pod(asset.unitScale);
  w.text(asset.unitSource);
  w.pod(static_cast<std::uint64_t>(asset.skeleton.joints.size()));
  for (const Joint& joint : asset.skeleton.joints) {
    w.text(joint.name);
    w.pod(static_cast<std::int32_t>(joint.parent));
    w.pod(joint.rest);
    w.pod(static_cast<std::uint8_t>(joint.inverseBind.has_value()));
    if (joint.inverseBind)
      w.pod(*joint.inverseBind);
  }
  w.pod(static_cast<std::uint64_t>(asset.clips.size()));
  for (const Clip& clip : asset.clips) {
    w.text(clip.name);
    w.pod(clip.fps);
    w.pod(static_cast<std::int32_t>(clip.frameCount));
    w.pod(static_cast<std::int32_t>(clip.jointCount));
    w.pod(static_cast<std::uint8_t>(clip.looping));
    w.array(clip.rotations);
    w.array(clip.translations);
    w.array(clip.scales);
    w.array(clip.hasRotation);
    w.array(clip.hasTranslation);
    w.array(clip.hasScale);
  }
  w.pod(static_cast<std::uint64_t>(asset.meshes.size()));
  for (const SkinnedMesh& mesh : asset.meshes) {
    w.text(mesh.name);
    w.array(mesh.positions);
    w.array(mesh.normals);
    w.array(mesh.uvs);
    w.array(mesh.indices);
    w.array(mesh.joints);
    w.array(mesh.weights);
    w.pod(static_cast<std::uint64_t>(mesh.parts.size()));
    for (const MeshPart& part : mesh.parts) {
      w.text(part.name);
      w.pod(part.firstIndex);
      w.pod(part.indexCount);
    }
  }
  w.pod(static_cast<std::uint64_t>(asset.warnings.size()));
  for (const std::string& warning : asset.warnings)
    w.text(warning);
  w.pod(static_cast<std::uint64_t>(asset.clusters.size()));
  for (const ClusterSet& set : asset.clusters) {
    w.pod(static_cast<std::int32_t>(set.frameCount));
    w.pod(static_cast<std::uint64_t>(set.joints.size()));
    for (const std::vector<Cluster>& joint : set.joints)
      w.array(joint);
  }
  w.flush();
  return w.ok();
}

Result<Asset> readAssetStream(std::string_view bytes) {
  if (bytes.size() < sizeof(kMagic) || std::memcmp(bytes.data(), kMagic, sizeof(kMagic)) != 0)
    return Error("the import worker sent no asset");
  Reader r(bytes.substr(sizeof(kMagic)));
  Asset asset;
  asset.sourcePath = r.text();
  asset.format = r.text();
  asset.unitScale = r.pod<double>();
  asset.unitSource = r.text();
  const auto joints = r.pod<std::uint64_t>();
  for (std::uint64_t i = 0; i < joints && !r.failed(); ++i) {
    Joint joint;
    joint.name = r.text();
    joint.parent = r.pod<std::int32_t>();
    joint.rest = r.pod<Transform>();
    if (r.pod<std::uint8_t>())
      joint.inverseBind = r.pod<glm::mat4>();
    asset.skeleton.joints.push_back(std::move(joint));
  }
  const auto clips = r.pod<std::uint64_t>();
  for (std::uint64_t i = 0; i < clips && !r.failed(); ++i) {
    Clip clip;
    clip.name = r.text();
    clip.fps = r.pod<double>();
    clip.frameCount = r.pod<std::int32_t>();
    clip.jointCount = r.pod<std::int32_t>();
    clip.looping = r.pod<std::uint8_t>() != 0;
    clip.rotations = r.array<glm::quat>();
    clip.translations = r.array<glm::vec3>();
    clip.scales = r.array<glm::vec3>();
    clip.hasRotation = r.array<std::uint8_t>();
    clip.hasTranslation = r.array<std::uint8_t>();
    clip.hasScale = r.array<std::uint8_t>();
    asset.clips.push_back(std::move(clip));
  }
  const auto meshes = r.pod<std::uint64_t>();
  for (std::uint64_t i = 0; i < meshes && !r.failed(); ++i) {
    SkinnedMesh mesh;
    mesh.name = r.text();
    mesh.positions = r.array<glm::vec3>();
    mesh.normals = r.array<glm::vec3>();
    mesh.uvs = r.array<glm::vec2>();
    mesh.indices = r.array<std::uint32_t>();
    mesh.joints = r.array<glm::u16vec4>();
    mesh.weights = r.array<glm::vec4>();
    const auto parts = r.pod<std::uint64_t>();
    for (std::uint64_t p = 0; p < parts && !r.failed(); ++p) {
      MeshPart part;
      part.name = r.text();
      part.firstIndex = r.pod<std::uint32_t>();
      part.indexCount = r.pod<std::uint32_t>();
      mesh.parts.push_back(std::move(part));
    }
    asset.meshes.push_back(std::move(mesh));
  }
  const auto warnings = r.pod<std::uint64_t>();
  for (std::uint64_t i = 0; i < warnings && !r.failed(); ++i)
    asset.warnings.push_back(r.text());
  const auto clusterSets = r.pod<std::uint64_t>();
  for (std::uint64_t i = 0; i < clusterSets && !r.failed(); ++i) {
    ClusterSet set;
    set.frameCount = r.pod<std::int32_t>();
    const auto clusterJoints = r.pod<std::uint64_t>();
    for (std::uint64_t j = 0; j < clusterJoints && !r.failed(); ++j)
      set.joints.push_back(r.array<Cluster>());
    asset.clusters.push_back(std::move(set));
  }
  if (r.failed())
    return Error("the import worker sent a truncated asset");
  if (Error error = asset.validate())
    return error;
  return asset;
}

} // namespace mlod

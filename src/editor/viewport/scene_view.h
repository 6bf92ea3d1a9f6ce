#pragma once
// The OpenGL 3.3 core view both viewports draw through (docs/architecture.md section 7): skinned meshes
// drawn instanced with their palettes in a texture (GPU skinning, resources/shaders/), a
// ground grid, coloured lines and points (the skeleton overlay) and overlay text. It holds
// no animation logic: the panels pose characters with the runtime and hand the palettes
// over. Camera: orbit, pan and dolly with Alt + left / middle / right drag (Maya) or the
// plain buttons, wheel to dolly, W A S D Q E to fly while a mouse button is held (as in
// Unreal and Unity: plain W toggles the Viewport's wireframe), F to frame. A click without a
// drag emits clicked() (joint picking). Each paint counts the triangles that reached the GPU
// (an OpenGL GL_PRIMITIVES_GENERATED query over the characters' draws).

#include "core/skinned_mesh.h"
#include "editor/viewport/orbit_camera.h"

#include <QOpenGLFunctions_3_3_Core>
#include <QOpenGLWidget>
#include <QStringList>

#include <glm/glm.hpp>

#include <memory>
#include <span>
#include <vector>

class QOpenGLShaderProgram;

namespace mlod {

// Whether this platform can show a QOpenGLWidget (the offscreen and minimal platforms
// cannot: a shown QOpenGLWidget crashes there) and create an OpenGL 3.3 context.
bool sceneViewSupported(QString* out_reason = nullptr);

class SceneView : public QOpenGLWidget, protected QOpenGLFunctions_3_3_Core {
  Q_OBJECT
public:
  struct Instance {
    glm::vec3 position{0.0f}; // cm, on the ground
    float yawRadians = 0.0f;
    glm::vec4 tint{0.8f, 0.8f, 0.8f, 1.0f};
  };
  // One instanced draw: `instances` copies of mesh `mesh`, instance k skinned by
  // palettes[k * joints .. (k + 1) * joints).
  struct Batch {
    int mesh = -1;
    int joints = 0;
    std::span<const glm::mat4> palettes;
    std::span<const Instance> instances;
    float alpha = 1.0f; // < 1: drawn blended after the opaque batches (a ghost)
  };
  struct LineVertex {
    glm::vec3 position{0.0f};
    glm::vec4 color{1.0f};
  };

  explicit SceneView(QWidget* parent = nullptr);
  ~SceneView() override;

  // Meshes, by id. A mesh that is not skinned is drawn rigidly with joint 0. Uploaded at the
  // next paint; ids stay valid until clearMeshes().
  int addMesh(const SkinnedMesh& mesh);
  void clearMeshes();

  // What the next paint draws. Palettes are copied at once (the spans may go afterwards).
  void setBatches(std::span<const Batch> batches);
  void setLines(std::vector<LineVertex> lines, std::vector<LineVertex> points);
  void setGrid(float extentCm, float stepCm);
  void setOverlay(const QStringList& lines) { m_overlay = lines; update(); }
  void setMessage(const QString& text) { m_message = text; update(); } // centred, when nothing is drawn

  OrbitCamera& camera() { return m_camera; }
  const OrbitCamera& camera() const { return m_camera; }
  // The view-projection of the current size (what the shaders use).
  glm::mat4 viewProjection() const;

  // Meshes drawn as lines (glPolygonMode), or filled.
  void setWireframe(bool on);
  bool wireframe() const { return m_wireframe; }
  // Triangles the last paint drew for the batches: as submitted (index counts x instances)
  // and as the GPU counted them (the query's result; -1 where the context has none).
  qint64 trianglesSubmitted() const { return m_trianglesSubmitted; }
  qint64 trianglesGenerated() const { return m_trianglesGenerated; }

  // GL_RENDERER and GL_VERSION of the context, once initialised.
  QString rendererInfo() const { return m_renderer; }
  bool glReady() const { return m_ready; }
  int paintCount() const { return m_paints; }

signals:
  void clicked(const QPoint& position);
  void frameRequested();
  void cameraChanged();
  void togglePlayRequested();

protected:
  void initializeGL() override;
  void paintGL() override;
  void mousePressEvent(QMouseEvent* event) override;
  void mouseMoveEvent(QMouseEvent* event) override;
  void mouseReleaseEvent(QMouseEvent* event) override;
  void wheelEvent(QWheelEvent* event) override;
  void keyPressEvent(QKeyEvent* event) override;
  bool event(QEvent* event) override;

private:
  struct GpuMesh {
    // Kept after upload: a new context (the dock floated or docked again gives the widget
    // another window, and with it another context) uploads it again.
    SkinnedMesh source;
    bool uploaded = false;
    unsigned vao = 0, vbo = 0, ibo = 0, instances = 0;
    int indexCount = 0;
  };
  void upload(GpuMesh& mesh);
  // Frees every GL object while its context is still there (it is about to go: the widget
  // moves to another window, or is destroyed); initializeGL() builds them anew.
  void releaseGL();
  void releaseMeshes(bool all); // all: every mesh (the context goes); else what clearMeshes() left
  // Returns the triangles submitted.
  qint64 drawBatches(const glm::mat4& viewProjection, bool transparent);
  void drawLines(const glm::mat4& viewProjection, bool grid);

  OrbitCamera m_camera;
  std::vector<std::unique_ptr<GpuMesh>> m_meshes;
  std::vector<unsigned> m_deadBuffers, m_deadArrays; // released at the next paint
  struct BatchInfo {
    int mesh = -1;
    int joints = 0;
    int instanceBegin = 0;
    int instanceCount = 0;
    int paletteTexel = 0;
    float alpha = 1.0f;
  };
  std::vector<BatchInfo> m_batches;
  std::vector<Instance> m_instances;
  std::vector<glm::vec4> m_texels; // palette rows, all batches
  bool m_texelsDirty = false;
  std::vector<LineVertex> m_lines, m_points, m_grid;
  QStringList m_overlay;
  QString m_message;

  std::unique_ptr<QOpenGLShaderProgram> m_skinned, m_lineProgram;
  unsigned m_paletteTexture = 0;
  int m_textureWidth = 4096;
  int m_textureRows = 0;
  unsigned m_lineVao = 0, m_lineVbo = 0;
  unsigned m_primitivesQuery = 0;
  bool m_wireframe = false;
  qint64 m_trianglesSubmitted = 0, m_trianglesGenerated = -1;
  bool m_ready = false;
  QString m_renderer;
  QString m_glError;
  int m_paints = 0;

  QPoint m_pressPosition, m_lastPosition;
  Qt::MouseButton m_dragButton = Qt::NoButton;
  bool m_dragged = false;
};

} // namespace mlod

// Mouse camera control for the preview, as in most 3D viewers: orbit the eye around the
// target (left drag), pan eye and target together in the image plane (right / middle
// drag), zoom by moving the eye along the view direction (wheel). Orbiting turns about
// the scene camera's up vector and never flips over its poles; `up` and fov never change.
#pragma once

#include "scene/scene.h"

namespace penumbra::preview {

class CameraController {
public:
    explicit CameraController(const Camera& initial);

    const Camera& camera() const { return m_camera; }

    // Drag deltas are in window pixels (x right, y down); `viewHeight` is the height in
    // pixels of the image on screen, so that a drag across the whole image orbits by
    // 180 degrees, and a pan keeps the point at the target's depth under the cursor.
    void orbit(double dx, double dy, double viewHeight);
    void pan(double dx, double dy, double viewHeight);
    // `steps` wheel notches; each moves the eye 10% of the way to the target (positive)
    // or back (negative).
    void zoom(double steps);
    // Back to the scene's camera.
    void reset() { m_camera = m_initial; }

private:
    Camera m_initial;
    Camera m_camera;
};

}  // namespace penumbra::preview

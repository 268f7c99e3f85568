// The CesiumJS viewer of the test pages (cesium.html, terrain.html), offline: no Ion token, no
// base imagery layer, no geocoder and none of the widgets, which would fetch from the network
// or cover the globe. `options` adds to these (a terrain provider, say).
// eslint-disable-next-line no-unused-vars
function offlineViewer(container, options = {}) {
  Cesium.Ion.defaultAccessToken = '';
  const viewer = new Cesium.Viewer(container, {
    baseLayer: false,
    baseLayerPicker: false,
    geocoder: false,
    homeButton: false,
    sceneModePicker: false,
    navigationHelpButton: false,
    animation: false,
    timeline: false,
    fullscreenButton: false,
    infoBox: false,
    selectionIndicator: false,
    ...options,
  });
  viewer.scene.globe.baseColor = Cesium.Color.DARKSLATEGRAY;
  return viewer;
}

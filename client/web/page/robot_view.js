// The A1 in 3D: robot/a1/a1.urdf through urdf-loader, posed from each state sample. The URDF has
// collision shapes only (no meshes), so those are what is drawn. Everything is z-up, as the URDF.
import * as THREE from 'three';
import { OrbitControls } from 'three/examples/jsm/controls/OrbitControls.js';
import URDFLoader from 'urdf-loader';

export class RobotView {
  constructor(container, urdfText) {
    this.container = container;
    this.renderer = new THREE.WebGLRenderer({ antialias: true, preserveDrawingBuffer: true });
    this.renderer.setPixelRatio(Math.min(window.devicePixelRatio, 2));
    container.appendChild(this.renderer.domElement);

    this.scene = new THREE.Scene();
    this.scene.background = new THREE.Color(0xe8eef4);
    this.scene.add(new THREE.HemisphereLight(0xffffff, 0x8090a0, 2.0));
    const sun = new THREE.DirectionalLight(0xffffff, 1.5);
    sun.position.set(2, -3, 5);
    this.scene.add(sun);
    // The floor's grid is a texture: long lines that pass behind the camera are not drawn by
    // every WebGL implementation (SwiftShader's among them).
    const floor = new THREE.MeshStandardMaterial({ map: gridTexture(), roughness: 0.9 });
    floor.map.repeat.set(40, 40);
    floor.map.anisotropy = this.renderer.capabilities.getMaxAnisotropy();
    this.scene.add(new THREE.Mesh(new THREE.PlaneGeometry(40, 40), floor));

    this.camera = new THREE.PerspectiveCamera(45, 1, 0.05, 100);
    this.camera.up.set(0, 0, 1);
    this.camera.position.set(-0.8, -1.0, 0.6);
    this.controls = new OrbitControls(this.camera, this.renderer.domElement);
    this.controls.target.set(0, 0, 0.25);

    const loader = new URDFLoader();
    loader.parseCollision = true;
    this.robot = loader.parse(urdfText);
    // Show the measured angles as they are, also where they pass the URDF's limits.
    for (const joint of Object.values(this.robot.joints)) joint.ignoreLimits = true;
    const body = new THREE.MeshStandardMaterial({ color: 0x3b4252, roughness: 0.6 });
    const limb = new THREE.MeshStandardMaterial({ color: 0xd08770, roughness: 0.5 });
    this.robot.traverse((o) => {
      if (o.isMesh) o.material = o.parent?.parent?.name === 'trunk' ? body : limb;
    });
    this.scene.add(this.robot);
    this.tick = -1;  // of the sample the scene shows

    new ResizeObserver(() => this.resize()).observe(container);
    this.resize();
    this.renderer.setAnimationLoop(() => this.render());
  }

  resize() {
    const w = this.container.clientWidth, h = this.container.clientHeight;
    this.renderer.setSize(w, h);
    this.camera.aspect = w / Math.max(h, 1);
    this.camera.updateProjectionMatrix();
  }

  // The measured joint angles (robot/a1.h order, named by jointNames) and base pose.
  show(state, jointNames) {
    jointNames.forEach((name, i) => this.robot.setJointValue(name, state.joint_position[i]));
    const [x, y, z] = state.position;
    const [w, qx, qy, qz] = state.orientation;
    // The camera follows the base, keeping the user's angle and distance.
    const moved = new THREE.Vector3(x, y, z).sub(this.robot.position);
    this.robot.position.set(x, y, z);
    this.robot.quaternion.set(qx, qy, qz, w);
    this.camera.position.add(moved);
    this.controls.target.add(moved);
    this.tick = state.tick;
  }

  // What the scene holds: its joints' angles by name and the tick they came from (for tests).
  jointAngles(jointNames) {
    return jointNames.map((name) => this.scene.getObjectByName(name).angle);
  }

  render() {
    this.controls.update();
    this.renderer.render(this.scene, this.camera);
  }
}

// One metre of floor: a light half-metre line and a darker line at the metre.
function gridTexture() {
  const canvas = document.createElement('canvas');
  canvas.width = canvas.height = 128;
  const g = canvas.getContext('2d');
  g.fillStyle = '#cfd6de';
  g.fillRect(0, 0, 128, 128);
  g.fillStyle = '#b3bdc8';
  g.fillRect(63, 0, 2, 128);
  g.fillRect(0, 63, 128, 2);
  g.fillStyle = '#7d8a99';
  g.fillRect(0, 0, 128, 3);
  g.fillRect(0, 0, 3, 128);
  const texture = new THREE.CanvasTexture(canvas);
  texture.wrapS = texture.wrapT = THREE.RepeatWrapping;
  texture.colorSpace = THREE.SRGBColorSpace;
  return texture;
}

// SPDX-License-Identifier: Apache-2.0
// vdbmap's 3D Tiles viewer (docs/viewer.md): three.js + 3d-tiles-renderer, served by
// `vdbmap view OUT` (tileset at /out/3dtiles/tileset.json). Bundled by build.mjs into
// dist/viewer.js; nothing is fetched from outside the server.
import {
	Clock, Color, DoubleSide, Group, MeshBasicMaterial,
	PerspectiveCamera, Raycaster, Scene, Sphere, Vector2, Vector3, WebGLRenderer,
} from 'three';
import { OrbitControls } from 'three/addons/controls/OrbitControls.js';
import { FlyControls } from 'three/addons/controls/FlyControls.js';
import { MeshoptDecoder } from 'three/addons/libs/meshopt_decoder.module.js';
import { TilesRenderer } from '3d-tiles-renderer/three';
import { GLTFExtensionsPlugin } from '3d-tiles-renderer/src/three/plugins/GLTFExtensionsPlugin.js';
import { featureColours, recordAtHit } from './features.js';
import { pathPositions, drivePathLine } from './drivePath.js';
import { areasFromReport, areasFromTileset, renderLegend } from './legend.js';

const params = new URLSearchParams( location.search );
const OUT = params.get( 'out' ) || '/out';
const TILESET_URL = `${ OUT }/3dtiles/tileset.json`;
const $ = id => document.getElementById( id );

// ---- scene: W (metres) is shown with its up axis along three's +y; tiles and the path live in W.
const renderer = new WebGLRenderer( { antialias: false, preserveDrawingBuffer: true } );
renderer.setPixelRatio( window.devicePixelRatio );
renderer.setSize( window.innerWidth, window.innerHeight );
$( 'view' ).append( renderer.domElement );
const scene = new Scene();
scene.background = new Color( 0x20252b );
const camera = new PerspectiveCamera( 60, window.innerWidth / window.innerHeight, 0.1, 1e5 );
const wFrame = new Group();
wFrame.name = 'W';
scene.add( wFrame );

const tiles = new TilesRenderer( TILESET_URL );
tiles.registerPlugin( new GLTFExtensionsPlugin( { meshoptDecoder: MeshoptDecoder, metadata: true } ) );
tiles.errorTarget = Number( params.get( 'errorTarget' ) || 16 );
tiles.setCamera( camera );
tiles.setResolutionFromRenderer( camera, renderer );
wFrame.add( tiles.group );

const orbit = new OrbitControls( camera, renderer.domElement );
orbit.screenSpacePanning = true;
const fly = new FlyControls( camera, renderer.domElement );
fly.dragToLook = true;
fly.rollSpeed = 0.6;
fly.enabled = false;

// ---- state shared with the page's controls and with tests (window.viewer)
const state = {
	mode: [ 'texture', 'class', 'confidence' ].includes( params.get( 'mode' ) ) ? params.get( 'mode' ) : 'texture',
	navigation: 'orbit',
	rootLoaded: false,
	loadedTiles: 0,
	fps: 0,
	errors: [],
	seenClasses: new Map(),
	areas: null,
	lastPick: null,
	sphere: new Sphere(),
	pathPositions: [],
	idleFrames: 0,
};
const classMaterial = new MeshBasicMaterial( { vertexColors: true, side: DoubleSide } );

function applyMode( mesh ) {

	const data = mesh.userData.vdbmapFeatures;
	const geometry = mesh.geometry;
	if ( state.mode === 'texture' || ! data ) {

		mesh.material = mesh.userData.vdbmapMaterial;
		if ( mesh.userData.vdbmapColor ) geometry.setAttribute( 'color', mesh.userData.vdbmapColor );
		else if ( data ) geometry.deleteAttribute( 'color' );
		return;

	}
	geometry.setAttribute( 'color', state.mode === 'class' ? data.classColors : data.confidenceColors );
	mesh.material = classMaterial;

}

function forEachTileMesh( fn ) {

	tiles.group.traverse( o => {

		if ( o.isMesh && o.userData.vdbmapMaterial ) fn( o );

	} );

}

function setMode( mode ) {

	state.mode = mode;
	forEachTileMesh( applyMode );
	for ( const b of document.querySelectorAll( '[data-mode]' ) ) b.classList.toggle( 'on', b.dataset.mode === mode );
	$( 'legend-box' ).style.display = mode === 'class' ? '' : 'none';
	$( 'confidence-box' ).style.display = mode === 'confidence' ? '' : 'none';

}

tiles.addEventListener( 'load-model', ( { scene: tileScene } ) => {

	state.loadedTiles ++;
	tileScene.traverse( o => {

		if ( ! o.isMesh ) return;
		// Textured mode is unlit: the atlas holds the camera's colours, already lit by the sun.
		const m = o.material;
		o.userData.vdbmapMaterial = new MeshBasicMaterial( { map: m.map || null, color: m.map ? 0xffffff : m.color, side: DoubleSide } );
		m.dispose();
		o.userData.vdbmapColor = o.geometry.getAttribute( 'color' ) || null;
		const data = featureColours( o );
		if ( data ) {

			o.userData.vdbmapFeatures = data;
			let added = false;
			for ( const [ id, c ] of data.classes ) {

				if ( ! state.seenClasses.has( id ) ) {

					state.seenClasses.set( id, c );
					added = true;

				}

			}
			if ( added ) refreshLegend();

		}
		applyMode( o );

	} );

} );
tiles.addEventListener( 'dispose-model', ( { scene: tileScene } ) => {

	state.loadedTiles --;
	// The renderer disposes the materials in use; the textured one may be swapped out.
	tileScene.traverse( o => {

		const m = o.isMesh ? o.userData.vdbmapMaterial : null;
		if ( m && m !== o.material ) {

			if ( m.map ) m.map.dispose();
			m.dispose();

		}

	} );

} );
tiles.addEventListener( 'load-error', ( e ) => {

	const message = `tile load failed: ${ e.url }: ${ e.error && e.error.message }`;
	state.errors.push( message );
	$( 'status' ).textContent = message;
	console.error( message );

} );
/**
 * W's up axis as a unit vector in W, from the root transform T (W -> tileset frame): the W
 * direction that T turns onto the tileset's up, which is +z (3D Tiles is z-up) or, for a
 * geo-referenced T (W -> ECEF, a large translation), the direction of T's origin from the
 * Earth's centre. Without a root transform: extras.up_axis (0/1/2 or 'x'/'y'/'z'), else z.
 */
function upAxisW( tileset, rootTransform ) {

	if ( rootTransform ) {

		const e = rootTransform.elements; // column-major
		const t = new Vector3( e[ 12 ], e[ 13 ], e[ 14 ] );
		const up = t.length() > 1e5 ? t.normalize() : new Vector3( 0, 0, 1 );
		const w = new Vector3(
			e[ 0 ] * up.x + e[ 1 ] * up.y + e[ 2 ] * up.z,
			e[ 4 ] * up.x + e[ 5 ] * up.y + e[ 6 ] * up.z,
			e[ 8 ] * up.x + e[ 9 ] * up.y + e[ 10 ] * up.z );
		if ( w.lengthSq() > 1e-12 ) return w.normalize();

	}
	const named = tileset && tileset.extras ? tileset.extras.up_axis : undefined;
	const index = typeof named === 'number' ? named : ( { x: 0, y: 1, z: 2 } )[ String( named ).toLowerCase() ];
	return new Vector3().setComponent( index === 0 || index === 1 ? index : 2, 1 );

}

tiles.addEventListener( 'load-root-tileset', ( { tileset } ) => {

	const root = tiles.root;
	const rootTransform = root && root.engineData && root.engineData.transform ? root.engineData.transform : null;
	// The root transform (W -> the tileset's z-up frame, or W -> ECEF when geo-referenced) is
	// undone, and W's up axis is turned to three.js's +y: the scene is W, shown upright.
	if ( rootTransform ) {

		tiles.group.matrix.copy( rootTransform ).invert();
		tiles.group.matrixAutoUpdate = false;

	}
	state.upW = upAxisW( tileset, rootTransform );
	wFrame.quaternion.setFromUnitVectors( state.upW, new Vector3( 0, 1, 0 ) );
	scene.updateMatrixWorld( true );
	tiles.getBoundingSphere( state.sphere );
	state.sphere.applyMatrix4( tiles.group.matrixWorld );
	state.rootLoaded = true;
	applyInitialView();

} );

// ---- views
const toThree = p => wFrame.localToWorld( new Vector3( p[ 0 ], p[ 1 ], p[ 2 ] ) );
const toW = v => wFrame.worldToLocal( v.clone() );

function setView( position, target ) {

	camera.position.copy( position );
	orbit.target.copy( target );
	camera.lookAt( target );
	const d = position.distanceTo( target );
	camera.near = Math.max( 0.05, d / 2000 );
	camera.far = Math.max( 1000, d * 20 + state.sphere.radius * 4 );
	camera.updateProjectionMatrix();
	orbit.update();

}

function overview() {

	const { center, radius } = state.sphere;
	const distance = 0.85 * radius / Math.sin( ( camera.fov * Math.PI / 180 ) / 2 );
	const dir = new Vector3( 0.45, 0.8, 0.55 ).normalize();
	setView( center.clone().addScaledVector( dir, distance ), center.clone() );

}

function applyInitialView() {

	const cam = params.get( 'cam' );
	const target = params.get( 'target' );
	if ( cam && target ) {

		setView( toThree( cam.split( ',' ).map( Number ) ), toThree( target.split( ',' ).map( Number ) ) );

	} else {

		overview();

	}

}

// ---- navigation switch (orbit / fly)
function setNavigation( kind ) {

	state.navigation = kind;
	orbit.enabled = kind === 'orbit';
	fly.enabled = kind === 'fly';
	fly.movementSpeed = Math.max( 2, state.sphere.radius / 8 );
	if ( kind === 'orbit' ) {

		const forward = new Vector3();
		camera.getWorldDirection( forward );
		orbit.target.copy( camera.position ).addScaledVector( forward, Math.max( 5, state.sphere.radius / 4 ) );
		orbit.update();

	}
	for ( const b of document.querySelectorAll( '[data-nav]' ) ) b.classList.toggle( 'on', b.dataset.nav === kind );

}

// ---- picking
const raycaster = new Raycaster();
const pointerDown = new Vector2();
function pick( clientX, clientY ) {

	const rect = renderer.domElement.getBoundingClientRect();
	const ndc = new Vector2( ( ( clientX - rect.left ) / rect.width ) * 2 - 1, - ( ( clientY - rect.top ) / rect.height ) * 2 + 1 );
	raycaster.setFromCamera( ndc, camera );
	const hits = raycaster.intersectObject( tiles.group, true );
	const hit = hits.find( h => h.object.userData.vdbmapMaterial );
	if ( ! hit ) {

		state.lastPick = null;
		$( 'pick' ).textContent = 'nothing under the cursor';
		return null;

	}
	const w = toW( hit.point );
	const r = recordAtHit( hit ) || {};
	state.lastPick = {
		classId: r.classId ?? null, name: r.name ?? null, rgb: r.rgb ?? null, confidence: r.confidence ?? null,
		W: [ w.x, w.y, w.z ],
	};
	const conf = r.confidence === null || r.confidence === undefined ? 'n/a' : r.confidence.toFixed( 3 );
	$( 'pick' ).textContent = `class ${ r.classId ?? '?' } ${ r.name ?? '' } · confidence ${ conf }\n` +
		`W: x ${ w.x.toFixed( 2 ) } y ${ w.y.toFixed( 2 ) } z ${ w.z.toFixed( 2 ) } m`;
	return state.lastPick;

}
renderer.domElement.addEventListener( 'pointerdown', e => pointerDown.set( e.clientX, e.clientY ) );
renderer.domElement.addEventListener( 'pointerup', e => {

	if ( Math.hypot( e.clientX - pointerDown.x, e.clientY - pointerDown.y ) < 4 && e.button === 0 ) pick( e.clientX, e.clientY );

} );

// ---- legend, drive path, report
function refreshLegend() {

	renderLegend( $( 'legend' ), state.seenClasses, state.areas );

}

async function fetchJson( url ) {

	const response = await fetch( url );
	if ( ! response.ok ) return null;
	return response.json();

}

fetchJson( `${ OUT }/3dtiles/drive_path.json` ).then( json => {

	state.pathPositions = json ? pathPositions( json ) : [];
	if ( state.pathPositions.length > 1 ) wFrame.add( drivePathLine( state.pathPositions ) );
	$( 'path-info' ).textContent = state.pathPositions.length > 1 ? `drive path: ${ state.pathPositions.length } poses` : 'drive path: none';

} ).catch( () => {} );
fetchJson( `${ OUT }/3dtiles/tileset.json` ).then( json => {

	const fromTileset = areasFromTileset( json );
	if ( fromTileset ) {

		state.areas = fromTileset;
		refreshLegend();
		return null;

	}
	return fetchJson( `${ OUT }/report.json` ).then( report => {

		state.areas = areasFromReport( report ) || state.areas;
		refreshLegend();

	} );

} ).catch( () => {} );

// ---- controls in the page
for ( const b of document.querySelectorAll( '[data-mode]' ) ) b.addEventListener( 'click', () => setMode( b.dataset.mode ) );
for ( const b of document.querySelectorAll( '[data-nav]' ) ) b.addEventListener( 'click', () => setNavigation( b.dataset.nav ) );
$( 'overview' ).addEventListener( 'click', () => {

	setNavigation( 'orbit' );
	overview();

} );
window.addEventListener( 'keydown', e => {

	if ( e.key === '1' ) setMode( 'texture' );
	if ( e.key === '2' ) setMode( 'class' );
	if ( e.key === '3' ) setMode( 'confidence' );
	if ( e.key === 'f' ) setNavigation( state.navigation === 'fly' ? 'orbit' : 'fly' );

} );
window.addEventListener( 'resize', () => {

	camera.aspect = window.innerWidth / window.innerHeight;
	camera.updateProjectionMatrix();
	renderer.setSize( window.innerWidth, window.innerHeight );
	tiles.setResolutionFromRenderer( camera, renderer );

} );

// ---- loop, counters
const clock = new Clock();
let frames = 0;
let lastCount = performance.now();
function loading() {

	const s = tiles.stats;
	return ( s.downloading || 0 ) + ( s.parsing || 0 ) + ( s.queued || 0 );

}
function frame() {

	requestAnimationFrame( frame );
	const dt = clock.getDelta();
	if ( state.navigation === 'fly' ) fly.update( dt );
	camera.updateMatrixWorld();
	scene.updateMatrixWorld();
	tiles.update();
	renderer.render( scene, camera );
	state.renderedTriangles = renderer.info.render.triangles;
	frames ++;
	state.idleFrames = state.rootLoaded && loading() === 0 ? state.idleFrames + 1 : 0;
	const now = performance.now();
	if ( now - lastCount >= 500 ) {

		state.fps = frames * 1000 / ( now - lastCount );
		frames = 0;
		lastCount = now;
		$( 'fps' ).textContent = `${ state.fps.toFixed( 1 ) } fps`;
		$( 'tiles' ).textContent = `tiles: ${ tiles.stats.visible || 0 } visible · ${ state.loadedTiles } loaded · ${ loading() } loading`;

	}

}
setMode( state.mode );
requestAnimationFrame( frame );

// ---- test and scripting hooks (tests/browser/*.mjs)
window.viewer = {
	state,
	setMode,
	setNavigation,
	overview,
	/** Camera at `position` looking at `target`, both [x, y, z] in W. */
	setViewW( position, target ) {

		setNavigation( 'orbit' );
		setView( toThree( position ), toThree( target ) );
		state.idleFrames = 0;

	},
	pick,
	/** Resolves once the root is loaded and nothing has been loading for `frames` frames. */
	whenIdle( frames = 5, timeoutMs = 60000 ) {

		const start = performance.now();
		return new Promise( ( resolve, reject ) => {

			const check = () => {

				if ( state.idleFrames >= frames ) resolve( { loadedTiles: state.loadedTiles, visible: tiles.stats.visible } );
				else if ( performance.now() - start > timeoutMs ) reject( new Error( 'tiles still loading after ' + timeoutMs + ' ms' ) );
				else setTimeout( check, 50 );

			};
			check();

		} );

	},
	/** Frames per second over `ms` milliseconds of continuous rendering. */
	measureFps( ms = 3000 ) {

		return new Promise( resolve => {

			let n = 0;
			const t0 = performance.now();
			const count = () => {

				n ++;
				if ( performance.now() - t0 < ms ) requestAnimationFrame( count );
				else resolve( n * 1000 / ( performance.now() - t0 ) );

			};
			requestAnimationFrame( count );

		} );

	},
};

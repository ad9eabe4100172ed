// SPDX-License-Identifier: Apache-2.0
// Writes a tiny hand-made 3D Tiles 1.1 tileset for the viewer's browser test, independent of
// the export.3dtiles writer: a 40 m x 20 m ground in W (z-up) in two leaves under one parent,
// a 4 m road strip along x (class 0, DATA.md colour 128 64 128) between sidewalks (class 1,
// 244 35 232). Each face is its own feature of a per-face table (confidence) and points at a
// class table (class id, name, colour): two feature-id sets, as EXT_mesh_features allows.
// Usage: node make_fixture.mjs OUT   (writes OUT/3dtiles/ and OUT/report.json)
import { mkdirSync, writeFileSync } from 'node:fs';
import { join } from 'node:path';

const out = process.argv[ 2 ];
if ( ! out ) {

	console.error( 'usage: node make_fixture.mjs OUT' );
	process.exit( 2 );

}
const CLASSES = [ { id: 0, name: 'road', rgb: [ 128, 64, 128 ] }, { id: 1, name: 'sidewalk', rgb: [ 244, 35, 232 ] } ];
const ROAD_HALF_WIDTH_M = 2;

/** Faces of a grid over [x0, x1] x [y0, y1] at z = 0 with `step` metres: [{tri: [[x,y,z] x3], cls}]. */
function groundFaces( x0, x1, y0, y1, step ) {

	const faces = [];
	for ( let x = x0; x < x1 - 1e-9; x += step ) {

		for ( let y = y0; y < y1 - 1e-9; y += step ) {

			const cls = Math.abs( y + step / 2 ) < ROAD_HALF_WIDTH_M ? 0 : 1;
			const a = [ x, y, 0 ], b = [ x + step, y, 0 ], c = [ x + step, y + step, 0 ], d = [ x, y + step, 0 ];
			faces.push( { tri: [ a, b, c ], cls }, { tri: [ a, c, d ], cls } );

		}

	}
	return faces;

}

function pad4( buffer, byte = 0 ) {

	const extra = ( 4 - ( buffer.length % 4 ) ) % 4;
	return Buffer.concat( [ buffer, Buffer.alloc( extra, byte ) ] );

}

/** A GLB of `faces` (W frame, written y-up as glTF requires) with the two feature-id sets. */
function glb( faces ) {

	const n = faces.length * 3;
	const pos = new Float32Array( n * 3 );
	const faceId = new Float32Array( n );
	const classId = new Float32Array( n );
	faces.forEach( ( f, i ) => f.tri.forEach( ( p, k ) => {

		const v = 3 * i + k;
		pos.set( [ p[ 0 ], p[ 2 ], - p[ 1 ] ], 3 * v ); // W (x, y, z) -> glTF y-up (x, z, -y)
		faceId[ v ] = i;
		classId[ v ] = f.cls;

	} ) );
	const min = [ 0, 1, 2 ].map( a => Math.min( ...pos.filter( ( _, i ) => i % 3 === a ) ) );
	const max = [ 0, 1, 2 ].map( a => Math.max( ...pos.filter( ( _, i ) => i % 3 === a ) ) );

	// property tables: classes (class_id UINT8, name STRING, color UINT8[3]); faces (confidence FLOAT32)
	const enc = new TextEncoder();
	const names = CLASSES.map( c => enc.encode( c.name ) );
	const offsets = new Uint32Array( CLASSES.length + 1 );
	names.forEach( ( s, i ) => ( offsets[ i + 1 ] = offsets[ i ] + s.length ) );
	const confidence = new Float32Array( faces.map( ( f, i ) => 0.5 + 0.5 * ( ( i % 7 ) / 6 ) ) );
	const chunks = [
		Buffer.from( pos.buffer ), Buffer.from( faceId.buffer ), Buffer.from( classId.buffer ),
		Buffer.from( Uint8Array.from( CLASSES.map( c => c.id ) ) ),
		Buffer.concat( names.map( s => Buffer.from( s ) ) ), Buffer.from( offsets.buffer ),
		Buffer.from( Uint8Array.from( CLASSES.flatMap( c => c.rgb ) ) ),
		Buffer.from( confidence.buffer ),
	];
	const views = [];
	let bin = Buffer.alloc( 0 );
	for ( const c of chunks ) {

		views.push( { buffer: 0, byteOffset: bin.length, byteLength: c.length } );
		bin = pad4( Buffer.concat( [ bin, c ] ) );

	}
	const json = {
		asset: { version: '2.0', generator: 'vdbmap tests/browser/make_fixture.mjs' },
		extensionsUsed: [ 'EXT_mesh_features', 'EXT_structural_metadata' ],
		scene: 0, scenes: [ { nodes: [ 0 ] } ], nodes: [ { mesh: 0 } ],
		materials: [ { pbrMetallicRoughness: { baseColorFactor: [ 0.6, 0.6, 0.55, 1 ], metallicFactor: 0 } } ],
		meshes: [ { primitives: [ {
			attributes: { POSITION: 0, _FEATURE_ID_0: 1, _FEATURE_ID_1: 2 }, material: 0, mode: 4,
			extensions: { EXT_mesh_features: { featureIds: [
				{ featureCount: faces.length, attribute: 0, propertyTable: 1, label: 'face_feature' },
				{ featureCount: CLASSES.length, attribute: 1, propertyTable: 0, label: 'semantic_class' },
			] } },
		} ] } ],
		accessors: [
			{ bufferView: 0, componentType: 5126, count: n, type: 'VEC3', min, max },
			{ bufferView: 1, componentType: 5126, count: n, type: 'SCALAR' },
			{ bufferView: 2, componentType: 5126, count: n, type: 'SCALAR' },
		],
		bufferViews: views,
		buffers: [ { byteLength: bin.length } ],
		extensions: { EXT_structural_metadata: {
			schema: { id: 'vdbmap_fixture', classes: {
				semantic_class: { properties: {
					class_id: { type: 'SCALAR', componentType: 'UINT8' },
					name: { type: 'STRING' },
					color: { type: 'SCALAR', componentType: 'UINT8', array: true, count: 3 },
				} },
				face: { properties: { confidence: { type: 'SCALAR', componentType: 'FLOAT32' } } },
			} },
			propertyTables: [
				{ class: 'semantic_class', count: CLASSES.length, properties: {
					class_id: { values: 3 }, name: { values: 4, stringOffsets: 5 }, color: { values: 6 } } },
				{ class: 'face', count: faces.length, properties: { confidence: { values: 7 } } },
			],
		} },
	};
	for ( let i = 1; i <= 2; i ++ ) json.bufferViews[ i ].target = 34962;
	const jsonBuf = pad4( Buffer.from( JSON.stringify( json ) ), 0x20 );
	const header = Buffer.alloc( 12 );
	header.writeUInt32LE( 0x46546c67, 0 );
	header.writeUInt32LE( 2, 4 );
	header.writeUInt32LE( 12 + 8 + jsonBuf.length + 8 + bin.length, 8 );
	const chunk = ( type, data ) => {

		const h = Buffer.alloc( 8 );
		h.writeUInt32LE( data.length, 0 );
		h.writeUInt32LE( type, 4 );
		return Buffer.concat( [ h, data ] );

	};
	return Buffer.concat( [ header, chunk( 0x4e4f534a, jsonBuf ), chunk( 0x004e4942, bin ) ] );

}

const box = ( cx, cy, cz, hx, hy, hz ) => ( { box: [ cx, cy, cz, hx, 0, 0, 0, hy, 0, 0, 0, hz ] } );
const dir = join( out, '3dtiles' );
mkdirSync( join( dir, 'tiles' ), { recursive: true } );
writeFileSync( join( dir, 'tiles', 'root.glb' ), glb( groundFaces( - 20, 20, - 10, 10, 4 ) ) );
writeFileSync( join( dir, 'tiles', 'leaf_0.glb' ), glb( groundFaces( - 20, 0, - 10, 10, 1 ) ) );
writeFileSync( join( dir, 'tiles', 'leaf_1.glb' ), glb( groundFaces( 0, 20, - 10, 10, 1 ) ) );
const tileset = {
	asset: { version: '1.1', generator: 'vdbmap tests/browser/make_fixture.mjs' },
	geometricError: 40,
	root: {
		boundingVolume: box( 0, 0, 0, 20, 10, 0.5 ), geometricError: 0.5, refine: 'REPLACE',
		content: { uri: 'tiles/root.glb' },
		children: [
			{ boundingVolume: box( - 10, 0, 0, 10, 10, 0.5 ), geometricError: 0, content: { uri: 'tiles/leaf_0.glb' } },
			{ boundingVolume: box( 10, 0, 0, 10, 10, 0.5 ), geometricError: 0, content: { uri: 'tiles/leaf_1.glb' } },
		],
	},
};
writeFileSync( join( dir, 'tileset.json' ), JSON.stringify( tileset, null, 1 ) );
const path = [];
for ( let x = - 18; x <= 18; x += 2 ) path.push( [ x, 0, 1.7 ] );
writeFileSync( join( dir, 'drive_path.json' ), JSON.stringify( { frame: 'W', positions_m: path } ) );
// The whole map's class areas as the semantic stage reports them (road 40 x 4, sidewalk 40 x 16).
writeFileSync( join( out, 'report.json' ), JSON.stringify( { stages: { 'semantic.mrf': { classes: {
	0: { name: 'road', faces: 0, area_m2: 160 }, 1: { name: 'sidewalk', faces: 0, area_m2: 640 } } } } } ) );
console.log( `fixture written to ${ out }` );

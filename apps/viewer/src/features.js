// SPDX-License-Identifier: Apache-2.0
// Per-vertex class and confidence colours from a tile's EXT_mesh_features feature ids and its
// EXT_structural_metadata property table(s), read through 3d-tiles-renderer's metadata
// extensions (mesh.userData.meshFeatures / structuralMetadata). The property names are found
// by meaning (class id, name, colour, confidence) so the viewer does not pin the writer's
// exact schema names.
import { BufferAttribute, Color, SRGBColorSpace } from 'three';

const _color = new Color();

/** [a, b, c] from an array, a typed array or a three.js Vector3/Color (a VEC3 property), else null. */
function triple( value ) {

	if ( ( Array.isArray( value ) || ArrayBuffer.isView( value ) ) && value.length >= 3 ) return Array.from( value ).slice( 0, 3 ).map( Number );
	if ( value && typeof value === 'object' ) {

		if ( 'x' in value && 'y' in value && 'z' in value ) return [ value.x, value.y, value.z ].map( Number );
		if ( 'r' in value && 'g' in value && 'b' in value ) return [ value.r, value.g, value.b ].map( Number );

	}
	return null;

}

/** A record {classId, name, rgb:[r,g,b] 0..255, confidence 0..1} from a property-table row. */
export function interpretRow( row ) {

	const out = { classId: null, name: null, rgb: null, confidence: null };
	if ( ! row ) return out;
	for ( const [ key, value ] of Object.entries( row ) ) {

		const k = key.toLowerCase();
		if ( value === null || value === undefined ) continue;
		if ( /conf/.test( k ) && typeof value === 'number' ) {

			out.confidence = value > 1 ? value / 255 : value;

		} else if ( /colou?r|rgb/.test( k ) && triple( value ) ) {

			const v = triple( value );
			const scale = v.some( x => x > 1 ) || v.every( Number.isInteger ) ? 1 : 255; // uint8 or 0..1 floats
			out.rgb = v.map( x => Math.round( x * scale ) );

		} else if ( /name/.test( k ) && typeof value === 'string' ) {

			out.name = value;

		} else if ( /(class|label)/.test( k ) && typeof value === 'number' ) {

			out.classId = value;

		}

	}
	return out;

}

/** Merges the rows of every feature-id set of one vertex into one record. */
function mergeRecords( records ) {

	const out = { classId: null, name: null, rgb: null, confidence: null };
	for ( const r of records ) {

		for ( const key of Object.keys( out ) ) {

			if ( out[ key ] === null && r[ key ] !== null ) out[ key ] = r[ key ];

		}

	}
	return out;

}

/** Looks a feature up in its property table once per (table, id). */
class RowCache {

	constructor( metadata ) {

		this.metadata = metadata;
		this.tables = new Map(); // table -> Array indexed by id
		this.empty = interpretRow( null );

	}

	get( table, id ) {

		if ( table === null || table === undefined || id === null || ! this.metadata ) return this.empty;
		let rows = this.tables.get( table );
		if ( ! rows ) this.tables.set( table, rows = [] );
		let record = rows[ id ];
		if ( ! record ) {

			let row = null;
			try {

				row = this.metadata.getPropertyTableData( table, id );

			} catch ( e ) {

				row = null;

			}
			record = rows[ id ] = interpretRow( row );

		}
		return record;

	}

}

/** Colour ramp for confidence 0..1: red (low) through yellow to green (high); grey if unknown. */
export function confidenceRgb( c ) {

	if ( c === null || c === undefined || Number.isNaN( c ) ) return [ 96, 96, 96 ];
	const t = Math.min( 1, Math.max( 0, c ) );
	return t < 0.5 ? [ 230, Math.round( 60 + 340 * t ), 40 ] : [ Math.round( 230 - 380 * ( t - 0.5 ) ), 230, 40 ];

}

function linear( rgb, array, offset ) {

	_color.setRGB( rgb[ 0 ] / 255, rgb[ 1 ] / 255, rgb[ 2 ] / 255, SRGBColorSpace );
	array[ offset ] = _color.r;
	array[ offset + 1 ] = _color.g;
	array[ offset + 2 ] = _color.b;

}

/**
 * For one mesh: {classColors, confidenceColors} (BufferAttributes, linear RGB, so that an
 * unlit material shows the table's sRGB colour exactly), the per-vertex records, and the
 * classes seen {classId -> {name, rgb}}. null when the mesh has no feature ids.
 */
export function featureColours( mesh ) {

	const features = mesh.userData.meshFeatures;
	if ( ! features ) return null;
	const geometry = mesh.geometry;
	const count = geometry.getAttribute( 'position' ).count;
	const info = features.getFeatureInfo();
	const cache = new RowCache( mesh.userData.structuralMetadata );
	const sets = info.map( ( fi ) => ( {
		table: fi.propertyTable,
		nullId: fi.nullFeatureId,
		attribute: 'attribute' in fi ? geometry.getAttribute( `_feature_id_${ fi.attribute }` ) : null,
	} ) );
	const classColors = new Float32Array( count * 3 );
	const confidenceColors = new Float32Array( count * 3 );
	const records = new Array( count );
	const classes = new Map();
	for ( let v = 0; v < count; v ++ ) {

		const parts = sets.map( s => {

			const id = s.attribute ? s.attribute.getX( v ) : v;
			return id === s.nullId ? interpretRow( null ) : cache.get( s.table, id );

		} );
		const r = parts.length === 1 ? parts[ 0 ] : mergeRecords( parts );
		records[ v ] = r;
		const rgb = r.rgb || [ 0, 0, 0 ];
		linear( rgb, classColors, 3 * v );
		linear( confidenceRgb( r.confidence ), confidenceColors, 3 * v );
		if ( r.classId !== null && ! classes.has( r.classId ) ) classes.set( r.classId, { name: r.name, rgb } );

	}
	return {
		classColors: new BufferAttribute( classColors, 3 ),
		confidenceColors: new BufferAttribute( confidenceColors, 3 ),
		records,
		classes,
	};

}

/** The record of the vertex nearest to a ray hit (the face's feature; faces do not share ids). */
export function recordAtHit( hit ) {

	const data = hit.object.userData.vdbmapFeatures;
	if ( ! data || ! hit.face ) return null;
	const { a, b, c } = hit.face;
	const bary = hit.barycoord;
	let v = a;
	if ( bary ) v = bary.x >= bary.y && bary.x >= bary.z ? a : ( bary.y >= bary.z ? b : c );
	return data.records[ v ];

}

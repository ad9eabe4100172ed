// SPDX-License-Identifier: Apache-2.0
// The drive path (OUT/3dtiles/drive_path.json, positions in the map frame W, metres) as a line.
import { BufferGeometry, Float32BufferAttribute, Line, LineBasicMaterial } from 'three';

/** The positions [[x, y, z], ...] found in drive_path.json, whatever its wrapping object. */
export function pathPositions( json ) {

	const isPoint = p => Array.isArray( p ) && p.length >= 3 && p.slice( 0, 3 ).every( x => typeof x === 'number' );
	const visit = ( value, depth ) => {

		if ( depth > 4 || value === null || typeof value !== 'object' ) return null;
		if ( Array.isArray( value ) ) {

			if ( value.length > 0 && value.every( isPoint ) ) return value.map( p => p.slice( 0, 3 ) );
			if ( value.length >= 3 && value.length % 3 === 0 && value.every( x => typeof x === 'number' ) ) {

				const out = [];
				for ( let i = 0; i < value.length; i += 3 ) out.push( value.slice( i, i + 3 ) );
				return out;

			}
			if ( value.length > 0 && value.every( p => p && typeof p === 'object' && ! Array.isArray( p ) ) ) {

				// [{position: [...]}, ...] or [{t_W_S: [...]}, ...]: the first point-like member.
				const out = value.map( p => Object.values( p ).find( isPoint ) ).filter( Boolean );
				if ( out.length === value.length ) return out.map( p => p.slice( 0, 3 ) );

			}
			return null;

		}
		const preferred = [ 'positions_m', 'positions', 'points', 'path', 'coordinates', 'poses' ];
		const keys = [ ...preferred.filter( k => k in value ), ...Object.keys( value ).filter( k => ! preferred.includes( k ) ) ];
		for ( const key of keys ) {

			const found = visit( value[ key ], depth + 1 );
			if ( found ) return found;

		}
		return null;

	};
	return visit( json, 0 ) || [];

}

export function drivePathLine( positions ) {

	const geometry = new BufferGeometry();
	geometry.setAttribute( 'position', new Float32BufferAttribute( positions.flat(), 3 ) );
	const material = new LineBasicMaterial( { color: 0x00e5ff, depthTest: false, transparent: true } );
	const line = new Line( geometry, material );
	line.renderOrder = 10;
	line.name = 'drive path';
	return line;

}

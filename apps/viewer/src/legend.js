// SPDX-License-Identifier: Apache-2.0
// The class legend: each class's colour (from the tiles' property tables) and area. The area
// is the whole map's: from the tileset (extras.classes: [{id, name, color, area_m2}] or
// {"<id>": {name, area_m2}}) when the writer puts it there,
// else from the run's report.json (stages.<semantic stage>.classes.<id>.area_m2).

/** {classId -> {name, area_m2}} from a tileset.json object, or null. */
export function areasFromTileset( tileset ) {

	const extras = tileset && tileset.extras;
	const classes = extras && ( extras.classes || ( extras.vdbmap && extras.vdbmap.classes ) );
	if ( ! classes ) return null;
	const out = new Map();
	const entries = Array.isArray( classes ) ? classes.map( c => [ c.id, c ] ) : Object.entries( classes );
	for ( const [ id, c ] of entries ) {

		if ( c && typeof c.area_m2 === 'number' ) {

			const rgb = Array.isArray( c.color || c.colour ) ? ( c.color || c.colour ).slice( 0, 3 ).map( Number ) : null;
			out.set( Number( id ), { name: c.name || String( id ), area_m2: c.area_m2, rgb } );

		}

	}
	return out.size ? out : null;

}

/** {classId -> {name, area_m2}} summed over the semantic stages of a report.json, or null. */
export function areasFromReport( report ) {

	const stages = report && report.stages;
	if ( ! stages ) return null;
	const out = new Map();
	for ( const stage of Object.values( stages ) ) {

		const classes = stage && stage.classes;
		if ( ! classes || typeof classes !== 'object' ) continue;
		for ( const [ id, c ] of Object.entries( classes ) ) {

			if ( ! c || typeof c.area_m2 !== 'number' ) continue;
			const prev = out.get( Number( id ) );
			out.set( Number( id ), { name: c.name || String( id ), area_m2: ( prev ? prev.area_m2 : 0 ) + c.area_m2 } );

		}

	}
	return out.size ? out : null;

}

function formatArea( m2 ) {

	if ( m2 === null || m2 === undefined ) return '';
	return m2 >= 1e4 ? ( m2 / 1e4 ).toFixed( 2 ) + ' ha' : m2.toFixed( m2 >= 100 ? 0 : 1 ) + ' m²';

}

/** Renders the legend into `element`: colours from `seen` (id -> {name, rgb}), areas from `areas`. */
export function renderLegend( element, seen, areas ) {

	// Classes in the loaded tiles, and those with an area in the map (not the label set's unused ones).
	const ids = new Set( [ ...seen.keys(), ...( areas ? [ ...areas ].filter( ( [ , a ] ) => a.area_m2 > 0 ).map( ( [ id ] ) => id ) : [] ) ] );
	const rows = [ ...ids ].map( id => ( {
		id,
		name: ( seen.get( id ) && seen.get( id ).name ) || ( areas && areas.get( id ) && areas.get( id ).name ) || `class ${ id }`,
		rgb: seen.get( id ) ? seen.get( id ).rgb : ( areas && areas.get( id ) && areas.get( id ).rgb ) || null,
		area: areas && areas.get( id ) ? areas.get( id ).area_m2 : null,
	} ) );
	rows.sort( ( a, b ) => ( b.area ?? - 1 ) - ( a.area ?? - 1 ) || a.id - b.id );
	element.innerHTML = '';
	for ( const r of rows ) {

		const row = document.createElement( 'div' );
		row.className = 'legend-row';
		const swatch = document.createElement( 'span' );
		swatch.className = 'swatch';
		swatch.style.background = r.rgb ? `rgb(${ r.rgb.join( ',' ) })` : 'transparent';
		const name = document.createElement( 'span' );
		name.textContent = `${ r.id } ${ r.name }`;
		const area = document.createElement( 'span' );
		area.className = 'area';
		area.textContent = formatArea( r.area );
		row.append( swatch, name, area );
		element.append( row );

	}
	return rows;

}

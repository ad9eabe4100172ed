// SPDX-License-Identifier: Apache-2.0
// The viewer in a real browser (ctest LABEL browser; docs/viewer.md): `vdbmap view OUT` in
// headless Debian chromium with software WebGL. Overview: waits until the tiles are loaded,
// screenshot, not blank, only upper levels fetched. Close-up above the drive path in class
// mode: leaves fetched, the pixel under the road has the road's colour from docs/DATA.md's
// label table, and a click there reports the road with W coordinates within 3 m (horizontally) of the path. No
// console errors anywhere.
// Usage: node viewer_test.mjs --vdbmap BIN --out OUT --data-md docs/DATA.md [--shots DIR] [--name NAME]
import { mkdirSync, readFileSync } from 'node:fs';
import { join } from 'node:path';
import {
	canvasStats, check, drivePathPoints, fail, fetchedContents, freshPage, launchChromium, startView, tilesetContents, upAxisW,
} from './lib.mjs';

const args = Object.fromEntries( process.argv.slice( 2 ).reduce( ( acc, a, i, all ) => {

	if ( a.startsWith( '--' ) ) acc.push( [ a.slice( 2 ), all[ i + 1 ] ] );
	return acc;

}, [] ) );
for ( const k of [ 'out', 'data-md' ] ) if ( ! args[ k ] ) fail( `missing --${ k }` );
const name = args.name || 'run';
const t0 = Date.now();

/** The road's colour from docs/DATA.md's label table ("| 0 | road | 128 64 128 |"). */
const stamp = what => console.log( `  ${ ( ( Date.now() - t0 ) / 1000 ).toFixed( 1 ) } s: ${ what }` );

function roadColour( dataMd ) {

	const m = readFileSync( dataMd, 'utf8' ).match( /\|\s*\d+\s*\|\s*road\s*\|\s*(\d+)\s+(\d+)\s+(\d+)\s*\|/ );
	if ( ! m ) fail( `${ dataMd }: no road row in the label table` );
	return m.slice( 1, 4 ).map( Number );

}

const ROAD = roadColour( args[ 'data-md' ] );
const contents = tilesetContents( args.out );
const leaves = [ ...contents ].filter( ( [ , c ] ) => c.leaf ).map( ( [ p ] ) => p );
check( leaves.length > 0, `${ name }: the tileset has ${ contents.size } contents, ${ leaves.length } leaves` );
const drive = JSON.parse( readFileSync( join( args.out, '3dtiles', 'drive_path.json' ), 'utf8' ) );

// --url: a server already running (development); otherwise `vdbmap view` is started here.
const server = args.url ? { url: args.url, process: { kill() {} } } : await startView( args.vdbmap, args.out );
const browser = await launchChromium();
let ok = false;
try {

	// One page (a WebGL context and SwiftShader's shader compiles cost seconds each): the
	// overview first, then the close-up with the request log emptied in between.
	const { page, log, context } = await freshPage( browser, 960, 600 );

	// ---- overview
	{

		await page.goto( server.url, { waitUntil: 'load' } );
		await page.waitForFunction( () => window.viewer && window.viewer.state.rootLoaded, { timeout: 30000 } );
		stamp( 'overview: root loaded' );
		const idle = await page.evaluate( () => window.viewer.whenIdle() );
		stamp( 'overview: tiles loaded' );
		const stats = await canvasStats( page );
		if ( args.shots ) await page.screenshot( { path: join( args.shots, `viewer_${ name }_overview.jpg` ), type: 'jpeg', quality: 85 } );
		check( stats.nonBackground > 0.05 && stats.distinctColours >= 3,
			`${ name } overview is not blank: ${ ( 100 * stats.nonBackground ).toFixed( 1 )} % of pixels drawn, ${ stats.distinctColours } colours, ${ idle.loadedTiles } tiles loaded` );
		const fetched = fetchedContents( log.requests, contents );
		const fetchedLeaves = fetched.filter( p => contents.get( p ).leaf );
		const foreign = log.requests.filter( u => ! u.startsWith( server.url ) && ! /^(data|blob):/.test( u ) );
		check( foreign.length === 0, `${ name }: the page fetched nothing but from vdbmap view (${ log.requests.length } requests)${ foreign.length ? ': ' + foreign.join( ' ' ) : '' }` );
		const parents = [ ...contents.values() ].filter( c => ! c.leaf ).length;
		check( parents > 0, `${ name }: the tileset has levels of detail (${ parents } parent contents)` );
		check( fetched.length > 0 && fetchedLeaves.length === 0,
			`${ name } overview fetched only upper levels: ${ fetched.length } contents (depths ${ [ ...new Set( fetched.map( p => contents.get( p ).depth ) ) ].sort().join( ',' ) }), no leaf of ${ leaves.length }` );
		if ( args.shots ) {

			await page.evaluate( () => window.viewer.setMode( 'class' ) );
			await new Promise( r => setTimeout( r, 500 ) );
			await page.screenshot( { path: join( args.shots, `viewer_${ name }_overview_classes.jpg` ), type: 'jpeg', quality: 85 } );

		}
		check( log.errors.length === 0, `${ name } overview: no console errors${ log.errors.length ? ': ' + log.errors.join( ' | ' ) : '' }` );

	}

	// ---- close-up above the middle of the drive path, in class mode
	{

		const positions = drivePathPoints( drive );
		const path = positions && positions.length ? positions : fail( `${ name }: drive_path.json has no positions` );
		// Behind the middle pose, looking at the ground 1.7 m below it (the sensor's height): the
		// road the vehicle drove on is at the centre of the view.
		const i = Math.floor( path.length / 2 );
		const p = path[ i ];
		const q = path[ Math.min( i + 1, path.length - 1 ) ], o = path[ Math.max( i - 1, 0 ) ];
		const up = upAxisW( JSON.parse( readFileSync( join( args.out, '3dtiles', 'tileset.json' ), 'utf8' ) ) );
		const d = [ 0, 1, 2 ].map( k => q[ k ] - o[ k ] );
		const along = d.reduce( ( a, x, k ) => a + x * up[ k ], 0 );
		const fwd = d.map( ( x, k ) => x - along * up[ k ] );
		const n = Math.hypot( ...fwd ) || 1;
		// 2 m above the ground and 1.5 m behind the pose: inside the leaves' bounding volumes, so
		// that any renderer refines to them.
		const target = [ 0, 1, 2 ].map( k => p[ k ] - 1.7 * up[ k ] );
		const cam = [ 0, 1, 2 ].map( k => p[ k ] + 0.3 * up[ k ] - 1.5 * fwd[ k ] / n );
		log.requests.length = 0;
		await page.evaluate( ( c, t ) => {

			window.viewer.setMode( 'class' );
			window.viewer.setViewW( c, t );

		}, cam, target );
		await page.evaluate( () => window.viewer.whenIdle() );
		stamp( 'close-up: tiles loaded' );
		const { width, height } = page.viewport();
		const centre = [ Math.round( width / 2 ), Math.round( height / 2 ) ];
		const stats = await canvasStats( page, [ centre ] );
		if ( args.shots ) await page.screenshot( { path: join( args.shots, `viewer_${ name }_closeup_classes.jpg` ), type: 'jpeg', quality: 85 } );
		check( stats.nonBackground > 0.5, `${ name } close-up is not blank: ${ ( 100 * stats.nonBackground ).toFixed( 1 ) } % drawn` );
		const px = stats.pixels[ 0 ];
		const diff = Math.max( ...px.map( ( v, i ) => Math.abs( v - ROAD[ i ] ) ) );
		check( diff <= 8, `${ name } class mode: the pixel under the drive path is the road's colour ${ ROAD.join( ' ' ) } (got ${ px.join( ' ' ) })` );
		const picked = await page.evaluate( ( x, y ) => window.viewer.pick( x, y ), centre[ 0 ], centre[ 1 ] );
		const horizontal = w => {

			const r = [ 0, 1, 2 ].map( k => w[ k ] - p[ k ] );
			const h = r.reduce( ( a, x, k ) => a + x * up[ k ], 0 );
			return Math.hypot( ...r.map( ( x, k ) => x - h * up[ k ] ) );

		};
		check( picked && picked.name === 'road' && horizontal( picked.W ) < 3,
			`${ name } click under the drive path: ${ JSON.stringify( picked ) }` );
		const fetched = fetchedContents( log.requests, contents );
		const fetchedLeaves = fetched.filter( q => contents.get( q ).leaf );
		check( fetchedLeaves.length > 0, `${ name } close-up fetched leaves: ${ fetchedLeaves.length } of ${ fetched.length } contents` );
		if ( args.shots ) {

			// For the docs: a street view 8 m up, 12 m behind the middle pose, in each mode.
			const camS = [ 0, 1, 2 ].map( k => p[ k ] + 8 * up[ k ] - 12 * fwd[ k ] / n );
			const targetS = [ 0, 1, 2 ].map( k => p[ k ] - 1.7 * up[ k ] + 6 * fwd[ k ] / n );
			await page.evaluate( ( c, t ) => window.viewer.setViewW( c, t ), camS, targetS );
			await page.evaluate( () => window.viewer.whenIdle() );
			for ( const mode of [ 'texture', 'class', 'confidence' ] ) {

				await page.evaluate( m => window.viewer.setMode( m ), mode );
				await new Promise( r => setTimeout( r, 500 ) );
				await page.screenshot( { path: join( args.shots, `viewer_${ name }_street_${ mode }.jpg` ), type: 'jpeg', quality: 85 } );

			}

		}
		check( log.errors.length === 0, `${ name } close-up: no console errors${ log.errors.length ? ': ' + log.errors.join( ' | ' ) : '' }` );
		await context.close();

	}
	ok = process.exitCode !== 1;

} finally {

	await browser.close();
	server.process.kill( 'SIGTERM' );
	console.log( `${ name }: ${ ok ? 'passed' : 'FAILED' } in ${ ( ( Date.now() - t0 ) / 1000 ).toFixed( 1 ) } s` );

}

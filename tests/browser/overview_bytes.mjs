// SPDX-License-Identifier: Apache-2.0
// Bytes a viewer fetches to its first complete overview of a tileset (issue 34): `vdbmap view
// OUT` in headless chromium, the viewer's own overview camera (the whole drive from above) at
// WIDTHxHEIGHT and its errorTarget (3d-tiles-renderer's maximum screen-space error, default
// 16), a fresh browser context (empty cache); waits until the tiles are loaded and idle, then
// sums the bytes of every response (tileset.json, drive_path.json, GLBs; the page and its
// script listed apart) and lists the contents fetched per level (bench/tiles3d_overview.sh).
// Usage: node overview_bytes.mjs --vdbmap BIN --out OUT [--width 1280 --height 800] [--error-target 16]
import { fail, freshPage, launchChromium, startView, tilesetContents } from './lib.mjs';

const args = Object.fromEntries( process.argv.slice( 2 ).reduce( ( acc, a, i, all ) => {

	if ( a.startsWith( '--' ) ) acc.push( [ a.slice( 2 ), all[ i + 1 ] ] );
	return acc;

}, [] ) );
if ( ! args.out || ! args.vdbmap ) fail( 'usage: node overview_bytes.mjs --vdbmap BIN --out OUT' );
const width = Number( args.width || 1280 );
const height = Number( args.height || 800 );
const errorTarget = Number( args[ 'error-target' ] || 16 );

const contents = tilesetContents( args.out );
const server = await startView( args.vdbmap, args.out );
const browser = await launchChromium();
try {

	const { page, log } = await freshPage( browser, width, height );
	const responses = [];
	page.on( 'response', async r => {

		let bytes = 0;
		try {

			bytes = ( await r.buffer() ).length;

		} catch ( e ) {

			bytes = Number( r.headers()[ 'content-length' ] || 0 );

		}
		responses.push( { url: r.url(), bytes } );

	} );
	const started = Date.now();
	await page.goto( `${ server.url }?errorTarget=${ errorTarget }`, { waitUntil: 'load' } );
	await page.waitForFunction( () => window.viewer && window.viewer.state.rootLoaded, { timeout: 600000 } );
	// Polled from here: a large tileset takes longer than one DevTools call may.
	let idle = null;
	while ( ! idle ) {

		idle = await page.evaluate( () => window.viewer.state.idleFrames >= 5 ?
			{ loadedTiles: window.viewer.state.loadedTiles } : null );
		if ( ! idle && Date.now() - started > 900000 ) fail( 'tiles still loading after 900 s' );
		if ( ! idle ) await new Promise( r => setTimeout( r, 1000 ) );

	}
	const seconds = ( Date.now() - started ) / 1000;
	await new Promise( r => setTimeout( r, 500 ) );  // the last responses' bodies
	let data = 0, app = 0;
	const perDepth = new Map();
	for ( const { url, bytes } of responses ) {

		const m = new URL( url ).pathname.match( /^\/out\/(.*)$/ );
		if ( ! m ) {

			app += bytes;
			continue;

		}
		data += bytes;
		const rel = decodeURIComponent( m[ 1 ] );
		const c = contents.get( rel );
		const key = c ? `depth ${ c.depth }${ c.leaf ? ' (leaf)' : '' }` : rel;
		const e = perDepth.get( key ) || { files: 0, bytes: 0 };
		e.files ++;
		e.bytes += bytes;
		perDepth.set( key, e );

	}
	console.log( `overview ${ width }x${ height }, errorTarget ${ errorTarget }: ${ idle.loadedTiles } tiles loaded, idle after ${ seconds.toFixed( 1 ) } s` );
	for ( const [ k, e ] of [ ...perDepth ].sort() ) console.log( `  ${ k }: ${ e.files } file(s), ${ e.bytes } bytes` );
	console.log( `tileset data fetched: ${ data } bytes (${ ( data / 1e6 ).toFixed( 2 ) } MB); the page and its script: ${ app } bytes` );
	if ( log.errors.length ) console.log( `console errors: ${ log.errors.join( ' | ' ) }` );

} finally {

	await browser.close();
	server.process.kill( 'SIGTERM' );

}

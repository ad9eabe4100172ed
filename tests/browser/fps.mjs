// SPDX-License-Identifier: Apache-2.0
// Frame rate of the viewer's overview in headless chromium with software WebGL (SwiftShader):
// `vdbmap view OUT`, overview, wait until the tiles are loaded, then REPEATS measurements of
// SECONDS of continuous rendering; prints each and the median (bench/viewer_fps.sh).
// Usage: node fps.mjs --vdbmap BIN --out OUT [--repeats 5] [--seconds 3] [--width 1280 --height 800]
import { fail, freshPage, launchChromium, startView } from './lib.mjs';

const args = Object.fromEntries( process.argv.slice( 2 ).reduce( ( acc, a, i, all ) => {

	if ( a.startsWith( '--' ) ) acc.push( [ a.slice( 2 ), all[ i + 1 ] ] );
	return acc;

}, [] ) );
if ( ! args.out || ! args.vdbmap ) fail( 'usage: node fps.mjs --vdbmap BIN --out OUT' );
const repeats = Number( args.repeats || 5 );
const seconds = Number( args.seconds || 3 );
const width = Number( args.width || 1280 );
const height = Number( args.height || 800 );

const server = await startView( args.vdbmap, args.out );
const browser = await launchChromium();
try {

	const { page, log } = await freshPage( browser, width, height );
	await page.goto( server.url, { waitUntil: 'load' } );
	await page.waitForFunction( () => window.viewer && window.viewer.state.rootLoaded, { timeout: 60000 } );
	const idle = await page.evaluate( () => window.viewer.whenIdle() );
	const fps = [];
	for ( let i = 0; i < repeats; i ++ ) fps.push( await page.evaluate( ms => window.viewer.measureFps( ms ), seconds * 1000 ) );
	const sorted = [ ...fps ].sort( ( a, b ) => a - b );
	const median = sorted[ Math.floor( sorted.length / 2 ) ];
	const triangles = await page.evaluate( () => window.viewer.state.renderedTriangles );
	console.log( `overview ${ width }x${ height }: ${ idle.loadedTiles } tiles loaded, ${ idle.visible } visible, ${ triangles } triangles drawn per frame` );
	console.log( `fps per run: ${ fps.map( f => f.toFixed( 2 ) ).join( ' ' ) }` );
	console.log( `median fps: ${ median.toFixed( 2 ) }` );
	if ( log.errors.length ) console.log( `console errors: ${ log.errors.join( ' | ' ) }` );

} finally {

	await browser.close();
	server.process.kill( 'SIGTERM' );

}
